// Recorded waypoints for se3_interpolate: poses and their times read from a CSV file
// (--waypoints) or a rosbag topic (--bag, --topic, --frame, --parent), so that a request file
// carries the options only (docs/command_line.md "Recorded waypoints").
//
// A CSV names its columns in its first line: t, x, y, z, qx, qy, qz and qw are found by name, in
// any order, and any other column is ignored (se3_interpolate's own output reads back). Every
// following line is one waypoint: waypoints[i] is line i + 2. The file is read a piece at a time
// (waypoints_csv.cpp): a bad header is refused before the rows are read. A bag gives one pose per
// geometry_msgs/PoseStamped or geometry_msgs/TransformStamped message, or per selected transform
// of a tf2_msgs/TFMessage, at its header.stamp; times count from the first pose's stamp.
//
// Errors are InvalidInputError naming the option, the file and, for a CSV, the line, the column
// and the byte offset.
// The checks of the poses themselves (unit quaternions, increasing times) are the request
// validation's; withRecordedOrigin adds the line or message a waypoints[i] or times[i] came from.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
namespace cli
{
/// Waypoints and their times from a recording, with where they came from.
struct RecordedWaypoints
{
  std::vector<Pose<double>> waypoints;
  std::vector<double> times;        ///< seconds: the CSV's t, or after the bag's first pose's stamp
  std::string frame_id;             ///< a bag's frame (header.frame_id or the transforms' parent); empty for a CSV
  std::int64_t time_origin_ns = 0;  ///< a bag's first stamp (ns since the epoch), at times = 0; 0 for a CSV
  std::string source;               ///< the option and file, e.g. "--waypoints 'recording.csv'"
  std::size_t first_line = 0;       ///< a CSV's line of waypoints[0] (2); 0 for a bag
  std::vector<std::uint64_t> line_offsets;  ///< a CSV's byte offset of each waypoint's line; empty for a bag
};

/// The columns a waypoints CSV must name in its header, in the order of its pose.
constexpr const char* kWaypointColumns[] = { "t", "x", "y", "z", "qx", "qy", "qz", "qw" };

/// The longest line of a waypoints CSV: a line is held whole while it is parsed (a waypoint's
/// line takes a few hundred bytes; a binary file's "line" can be the whole file).
constexpr std::size_t kMaxCsvLineBytes = std::size_t(1) << 20;

/// Reads `--waypoints FILE.csv` a piece of 64 KiB at a time, each line parsed when it is complete
/// (the rules of parseWaypointsCsv), so that memory holds the waypoints and one line.
/// @throws InvalidInputError naming the file (cannot be read), or as parseWaypointsCsv, as soon as
///         the line at fault is read
RecordedWaypoints readWaypointsCsv(const std::string& path, std::size_t max_rows = SIZE_MAX);

/// Parses the text of a waypoints CSV: the header names the columns (kWaypointColumns by name, any
/// order, others ignored; a UTF-8 byte order mark before it is skipped); each following line has
/// as many cells as the header, and its named cells are finite numbers (std::from_chars; spaces
/// around a cell are allowed). Lines end at '\n', "\r\n" or a lone '\r'; the last may have no end.
/// @param path the file's name, for messages
/// @param max_rows the most waypoints taken: the file is refused at the line after them
/// @throws InvalidInputError naming `path`, the line (1-based), the column (1-based, in bytes) and
///         the byte offset in the file (0-based) where the fault starts, quoting cells with
///         control bytes (a NUL too) as \xHH: an empty file, a UTF-16 file, a line longer than
///         kMaxCsvLineBytes, a header without a column or with one twice, a line with the wrong
///         number of cells, a cell that is not a finite number, more than max_rows rows, no rows
RecordedWaypoints parseWaypointsCsv(std::string_view text, const std::string& path, std::size_t max_rows = SIZE_MAX);

/// Which poses of a bag to read (the options --bag, --topic, --frame, --parent).
struct BagSelection
{
  std::string path;    ///< --bag
  std::string topic;   ///< --topic
  std::string frame;   ///< --frame: the transforms' child_frame_id (required for a tf2_msgs/TFMessage topic)
  std::string parent;  ///< --parent: the frame the poses are given in; empty: the recorded one, if unique
};

/// Reads the poses `selection` names from a bag, each at its header.stamp, with times in seconds
/// after the first pose's stamp; frame_id is their recorded frame (header.frame_id or the parent).
/// @throws InvalidInputError naming the option: the bag cannot be opened (--bag); no message on
///         the topic (--topic, listing the bag's topics); a message type other than
///         geometry_msgs/PoseStamped, geometry_msgs/TransformStamped and tf2_msgs/TFMessage
///         (--topic); --frame missing for a TFMessage or given for a PoseStamped, or no transform
///         of it (--frame, listing the child frames); poses in several frames without --parent,
///         or none in the --parent frame (--parent, naming the frames)
RecordedWaypoints readWaypointsBag(const BagSelection& selection);

/// Where waypoints[i] came from: "line N, column 1 (byte offset B) of --waypoints 'f.csv'" or
/// "pose i of --bag 'f.bag' --topic /t".
std::string recordedOrigin(const RecordedWaypoints& recorded, std::size_t i);

/// `message` with the origin of the first waypoints[i] or times[i] it names appended (the request
/// validation names the index only); unchanged if it names none.
std::string withRecordedOrigin(const std::string& message, const RecordedWaypoints& recorded);

}  // namespace cli
}  // namespace se3_interpolation
