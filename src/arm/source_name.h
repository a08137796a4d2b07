// The arm model's messages name their input file: a long path keeps its end (the file's name).
#pragma once

#include <string>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace arm
{
/// `source` (a path or a caller's label) for an error message: quotedText of it, or of its last
/// kMaxQuotedLength characters after "..." when longer, so that a long path keeps the file's name.
inline std::string quotedSource(const std::string& source)
{
  if (source.size() <= kMaxQuotedLength)
    return quotedText(source);
  return "'..." + quotedText(source.substr(source.size() - kMaxQuotedLength)).substr(1);
}
}  // namespace arm
}  // namespace se3_interpolation
