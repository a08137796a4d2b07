// Error types of the core library (modelled on tf2's exception hierarchy).
//
// Every error the mathematics can raise derives from std::invalid_argument, so a
// caller that only wants "bad input, here is why" catches that; callers that need
// to react differently catch the specific type. Messages name the offending
// request field and index, e.g. "waypoints[3].orientation: ...".
#pragma once

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>

namespace se3_interpolation
{
/// Base of every error thrown by the core: the input cannot produce a curve.
class InterpolationError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// A request field is malformed (non-finite, out of range, wrong length, unknown name).
class InvalidInputError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// Two points to be joined are exactly antipodal (rotation angle π, or x and −x on
/// S^m): the minimising geodesic between them is not unique.
class NonUniqueGeodesicError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// An iterative solve (interpolating spline) did not reach its tolerance.
class ConvergenceError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

/// A request would exceed a configured resource limit (samples, waypoints).
class LimitExceededError : public InterpolationError
{
public:
  using InterpolationError::InterpolationError;
};

// --- Message helpers: the one spelling of an indexed field, a number and quoted user text ----

/// "field[i]".
inline std::string indexedField(const std::string& field, std::size_t i)
{
  return field + "[" + std::to_string(i) + "]";
}

/// A number with 17 significant digits (round-trips).
inline std::string formatNumber(double x)
{
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

/// Longest error text the node logs or returns: an exception from tf2 or roscpp may quote
/// strings of any length.
constexpr std::size_t kMaxMessageLength = 1024;

/// `message` cut to kMaxMessageLength characters (marked "... (truncated)").
inline std::string boundedMessage(const std::string& message)
{
  return message.size() <= kMaxMessageLength ? message : message.substr(0, kMaxMessageLength) + "... (truncated)";
}

/// At most this many characters of user text are quoted in an error message, so that no
/// message or log line carries an unbounded string.
constexpr std::size_t kMaxQuotedLength = 40;

/// `text` for an error message (named apart from std::quoted, which argument-dependent lookup
/// would pick for a non-const std::string): at most kMaxQuotedLength characters in single quotes, control
/// and non-ASCII bytes as \xHH, and "... (N characters)" when cut.
inline std::string quotedText(const std::string& text)
{
  static const char* kHex = "0123456789ABCDEF";
  std::string out = "'";
  const std::size_t n = std::min(text.size(), kMaxQuotedLength);
  for (std::size_t i = 0; i < n; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c >= 0x7F)
    {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xF];
    }
    else
      out += static_cast<char>(c);
  }
  out += "'";
  if (text.size() > n)
    out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

}  // namespace se3_interpolation
