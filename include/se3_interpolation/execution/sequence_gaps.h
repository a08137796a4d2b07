// execution/sequence_gaps.h: messages lost before they reached the node, seen as gaps in the
// sequence numbers each publisher gives its messages (roscpp numbers header.seq per publisher).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace se3_interpolation
{
/// Per publisher, the latest sequence number; not thread-safe (one intake thread per topic).
class SequenceGaps
{
public:
  /// Publishers remembered at once: beyond, all are forgotten (a flood of publisher names must not
  /// grow memory without bound); a forgotten publisher's next message counts no gap.
  static constexpr std::size_t kMaxTrackedPublishers = 1000;

  /// The messages `publisher` skipped between its previous message and this one numbered `seq`:
  /// 0 for its first message, for a restart (a smaller number) and for a publisher that does not
  /// number its messages (the same number again).
  std::uint64_t observe(const std::string& publisher, std::uint32_t seq)
  {
    if (last_.size() >= kMaxTrackedPublishers && last_.count(publisher) == 0)
      last_.clear();
    auto it = last_.find(publisher);
    std::uint64_t gap = 0;
    if (it != last_.end() && seq > it->second + 1ULL)
      gap = seq - it->second - 1ULL;
    last_[publisher] = seq;
    return gap;
  }

  std::size_t trackedPublishers() const { return last_.size(); }

private:
  std::map<std::string, std::uint32_t> last_;
};

}  // namespace se3_interpolation
