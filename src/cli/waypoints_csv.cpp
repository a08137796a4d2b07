// The waypoints CSV of se3_interpolate --waypoints (recorded_waypoints.h): read a piece at a time,
// each line parsed as soon as it is complete, so that a bad header is refused before the rows are
// read and memory holds the waypoints and one line, whatever the file's size.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

#include "recorded_waypoints.h"
#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace cli
{
namespace
{
constexpr std::size_t kColumnCount = sizeof(kWaypointColumns) / sizeof(kWaypointColumns[0]);

/// The piece a file is read in.
constexpr std::size_t kReadPiece = std::size_t(64) << 10;

/// The header cells a refusal of the header lists, at most.
constexpr std::size_t kListedHeaderCells = 12;

/// One cell of a line: its text (not trimmed) and its 0-based byte column in the line.
struct Cell
{
  std::string_view text;
  std::size_t column;
};

/// The cells of one line, split at every comma.
std::vector<Cell> splitCells(std::string_view line)
{
  std::vector<Cell> cells;
  std::size_t start = 0;
  for (;;)
  {
    const std::size_t comma = line.find(',', start);
    cells.push_back(
        { line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start), start });
    if (comma == std::string_view::npos)
      return cells;
    start = comma + 1;
  }
}

/// `text` without spaces at either end.
std::string_view trimmed(std::string_view text)
{
  while (!text.empty() && text.front() == ' ')
    text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ')
    text.remove_suffix(1);
  return text;
}

bool startsWith(std::string_view text, std::string_view prefix)
{
  return text.substr(0, prefix.size()) == prefix;
}

/// Parses a waypoints CSV handed on in pieces (the rules of parseWaypointsCsv). Lines end at '\n',
/// "\r\n" or a lone '\r'; a '\r' at the end of a piece may be the first half of a "\r\n".
class CsvReader
{
public:
  CsvReader(const std::string& path, std::size_t max_rows) : max_rows_(max_rows)
  {
    r_.source = "--waypoints '" + path + "'";
    r_.first_line = 2;
  }

  /// Takes the next piece of the file: every line it completes is parsed.
  void add(std::string_view piece)
  {
    const std::uint64_t base = offset_;
    offset_ += piece.size();
    std::size_t pos = 0;
    if (cr_ended_piece_ && !piece.empty())
    {
      cr_ended_piece_ = false;
      if (piece.front() == '\n')
        next_line_offset_ = base + (pos = 1);
    }
    while (pos < piece.size())
    {
      const std::size_t end = piece.find_first_of("\r\n", pos);
      if (end == std::string_view::npos)
      {
        keep(piece.substr(pos));
        return;
      }
      if (pending_.empty())
        completeLine(piece.substr(pos, end - pos));
      else
      {
        keep(piece.substr(pos, end - pos));
        completeLine(pending_);
        pending_.clear();
      }
      pos = end + 1;
      if (piece[end] == '\r' && pos == piece.size())
        cr_ended_piece_ = true;
      else if (piece[end] == '\r' && piece[pos] == '\n')
        ++pos;
      next_line_offset_ = base + pos;
    }
  }

  /// The end of the file: its last line (one without a line end) parsed, then the checks of the whole.
  RecordedWaypoints finish()
  {
    if (!pending_.empty())
      completeLine(pending_);
    if (line_ == 0)
      refuse(1, 0, 0, "the file is empty; expected a header naming the columns t,x,y,z,qx,qy,qz,qw");
    if (r_.waypoints.empty())
      refuse(2, offset_, 0, "no rows after the header; expected one waypoint per line");
    return std::move(r_);
  }

private:
  /// Refused at `line` (1-based), `column` (0-based byte in the line) and `byte` (the file's offset
  /// of the line's start), which the message names as line, column (1-based) and byte offset.
  [[noreturn]] void refuse(std::size_t line, std::uint64_t byte, std::size_t column, const std::string& why) const
  {
    throw InvalidInputError(r_.source + " line " + std::to_string(line) + ", column " + std::to_string(column + 1) +
                            " (byte offset " + std::to_string(byte + column) + "): " + why);
  }
  [[noreturn]] void refuseHere(std::size_t column, const std::string& why) const
  {
    refuse(line_, line_offset_, column, why);
  }

  /// Keeps the start of a line whose end is in a later piece.
  void keep(std::string_view text)
  {
    if (pending_.size() + text.size() > kMaxCsvLineBytes)
      refuse(line_ + 1, next_line_offset_, 0, longLine());
    pending_.append(text);
  }

  static std::string longLine()
  {
    return "the line is longer than " + std::to_string(kMaxCsvLineBytes) +
           " bytes (a waypoint takes a few hundred; is this a CSV file?)";
  }

  void completeLine(std::string_view text)
  {
    ++line_;
    line_offset_ = next_line_offset_;
    if (text.size() > kMaxCsvLineBytes)
      refuseHere(0, longLine());
    if (line_ == 1)
      header(text);
    else
      row(text);
  }

  void header(std::string_view text)
  {
    // A UTF-8 byte order mark (a spreadsheet's export) is no part of the first column's name.
    if (startsWith(text, "\xEF\xBB\xBF"))
    {
      text.remove_prefix(3);
      line_offset_ += 3;
    }
    if (startsWith(text, "\xFF\xFE") || startsWith(text, "\xFE\xFF"))
      refuseHere(0, "the file starts with a UTF-16 byte order mark (" +
                        std::string(text[0] == '\xFF' ? "FF FE" : "FE FF") +
                        "): it is UTF-16 text; save it as UTF-8 or ASCII");
    const std::vector<Cell> cells = splitCells(text);
    role_.assign(cells.size(), kColumnCount);
    std::array<std::size_t, kColumnCount> column;
    column.fill(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c)
      for (std::size_t k = 0; k < kColumnCount; ++k)
        if (trimmed(cells[c].text) == kWaypointColumns[k])
        {
          if (column[k] != cells.size())
            refuseHere(cells[c].column, "column '" + std::string(kWaypointColumns[k]) + "' named twice (cells " +
                                            std::to_string(column[k] + 1) + " and " + std::to_string(c + 1) + ")");
          column[k] = c;
          role_[c] = k;
        }
    for (std::size_t k = 0; k < kColumnCount; ++k)
      if (column[k] == cells.size())
      {
        std::string listed;
        for (std::size_t c = 0; c < std::min(cells.size(), kListedHeaderCells); ++c)
          listed += (c ? ", " : "") + quotedText(std::string(cells[c].text));
        if (cells.size() > kListedHeaderCells)
          listed += ", ... (" + std::to_string(cells.size()) + " cells)";
        refuseHere(0, "column '" + std::string(kWaypointColumns[k]) +
                          "': missing from the header (t,x,y,z,qx,qy,qz,qw are found by name, in any order; its "
                          "cells: " +
                          listed + ")");
      }
  }

  void row(std::string_view text)
  {
    if (r_.waypoints.size() == max_rows_)
      refuseHere(0, "more than " + std::to_string(max_rows_) + " waypoints, the most se3_interpolate takes");
    const std::size_t count = static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1;
    if (count != role_.size())
      refuseHere(count > role_.size() ? splitCells(text)[role_.size()].column : text.size(),
                 std::to_string(count) + (count == 1 ? " cell" : " cells") + ", but the header (line 1) has " +
                     std::to_string(role_.size()));
    std::array<double, kColumnCount> v{};
    std::size_t start = 0;
    for (std::size_t c = 0; c < role_.size(); ++c)
    {
      const std::size_t comma = text.find(',', start);
      if (role_[c] < kColumnCount)
      {
        const std::string_view cell =
            trimmed(text.substr(start, comma == std::string_view::npos ? comma : comma - start));
        double& value = v[role_[c]];
        const std::from_chars_result parsed = std::from_chars(cell.data(), cell.data() + cell.size(), value);
        if (parsed.ec != std::errc() || parsed.ptr != cell.data() + cell.size() || !std::isfinite(value))
          refuseHere(start, "cell " + std::to_string(c + 1) + " (column '" + kWaypointColumns[role_[c]] +
                                "'): " + quotedText(std::string(cell)) + " is not a finite number");
      }
      start = comma + 1;
    }
    r_.times.push_back(v[0]);
    r_.waypoints.emplace_back(Quaternion<double>(v[7], v[4], v[5], v[6]), Vector3<double>(v[1], v[2], v[3]));
    r_.line_offsets.push_back(line_offset_);
  }

  RecordedWaypoints r_;
  std::size_t max_rows_;
  std::string pending_;                 ///< the start of a line whose end is in a later piece
  bool cr_ended_piece_ = false;         ///< the last piece ended in '\r' (a '\n' next is its "\r\n")
  std::uint64_t offset_ = 0;            ///< bytes of the file taken so far
  std::uint64_t next_line_offset_ = 0;  ///< the file's offset of the next line's start
  std::uint64_t line_offset_ = 0;       ///< the file's offset of the line being parsed
  std::size_t line_ = 0;                ///< its number (1-based); 0 before the first
  /// role_[c]: which of kWaypointColumns header cell c is, or kColumnCount for another column.
  std::vector<std::size_t> role_;
};
}  // namespace

RecordedWaypoints parseWaypointsCsv(std::string_view text, const std::string& path, std::size_t max_rows)
{
  CsvReader reader(path, max_rows);
  reader.add(text);
  return reader.finish();
}

RecordedWaypoints readWaypointsCsv(const std::string& path, std::size_t max_rows)
{
  const std::string what = "--waypoints '" + path + "'";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw InvalidInputError(what + ": cannot be read: " + std::strerror(errno));
  CsvReader reader(path, max_rows);
  std::string piece(kReadPiece, '\0');
  try
  {
    for (;;)
    {
      const ssize_t n = ::read(fd, &piece[0], piece.size());
      if (n < 0 && errno == EINTR)
        continue;
      if (n < 0)
        throw InvalidInputError(what + ": cannot be read: " + std::strerror(errno));
      if (n == 0)
        break;
      reader.add(std::string_view(piece.data(), static_cast<std::size_t>(n)));
    }
  }
  catch (...)
  {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return reader.finish();
}

}  // namespace cli
}  // namespace se3_interpolation
