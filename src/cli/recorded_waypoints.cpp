#include "recorded_waypoints.h"

#include <fcntl.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <system_error>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace cli
{
namespace
{
constexpr std::size_t kColumnCount = sizeof(kWaypointColumns) / sizeof(kWaypointColumns[0]);

/// `text` without spaces at either end and without a final '\r' (a CRLF file).
std::string_view trimmed(std::string_view text)
{
  if (!text.empty() && text.back() == '\r')
    text.remove_suffix(1);
  while (!text.empty() && text.front() == ' ')
    text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ')
    text.remove_suffix(1);
  return text;
}

/// The cells of one line, split at every comma (not trimmed).
std::vector<std::string_view> splitCells(std::string_view line)
{
  std::vector<std::string_view> cells;
  for (;;)
  {
    const std::size_t comma = line.find(',');
    cells.push_back(line.substr(0, comma));
    if (comma == std::string_view::npos)
      return cells;
    line.remove_prefix(comma + 1);
  }
}

/// "'a', 'b'" of a set of names.
std::string quotedList(const std::set<std::string>& names)
{
  std::string list;
  for (const std::string& name : names)
    list += (list.empty() ? "'" : ", '") + name + "'";
  return list;
}

std::string readWholeFile(const std::string& path, const std::string& what)
{
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw InvalidInputError(what + ": cannot be read: " + std::strerror(errno));
  std::string text;
  std::size_t size = 0;
  for (;;)
  {
    if (text.size() - size < (std::size_t(1) << 16))
      text.resize(std::max<std::size_t>(2 * text.size(), std::size_t(1) << 20));
    const ssize_t n = ::read(fd, &text[size], text.size() - size);
    if (n < 0 && errno == EINTR)
      continue;
    if (n < 0)
    {
      const int error = errno;
      ::close(fd);
      throw InvalidInputError(what + ": cannot be read: " + std::strerror(error));
    }
    if (n == 0)
      break;
    size += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(size);
  return text;
}

/// One pose of a bag before selection: its frames, stamp and pose.
struct StampedPose
{
  std::string parent;
  std::string child;
  ros::Time stamp;
  Pose<double> pose;
};

const char* const kPoseStamped = "geometry_msgs/PoseStamped";
const char* const kTransformStamped = "geometry_msgs/TransformStamped";
const char* const kTfMessage = "tf2_msgs/TFMessage";

StampedPose fromTransform(const geometry_msgs::TransformStamped& t)
{
  const geometry_msgs::Vector3& p = t.transform.translation;
  const geometry_msgs::Quaternion& q = t.transform.rotation;
  return { t.header.frame_id, t.child_frame_id, t.header.stamp,
           Pose<double>(Quaternion<double>(q.w, q.x, q.y, q.z), Vector3<double>(p.x, p.y, p.z)) };
}

/// Every pose on the selection's topic, in the bag's order; the topic's checks (messages, type).
/// Every child frame of its transforms goes into `children`; of a TFMessage, only the transforms of
/// the selection's --frame are kept.
std::vector<StampedPose> readTopic(rosbag::Bag& bag, const BagSelection& selection, std::string* datatype,
                                   std::set<std::string>* children)
{
  const std::string topic = "--topic '" + selection.topic + "'";
  rosbag::View view(bag, rosbag::TopicQuery(selection.topic));
  if (view.size() == 0)
  {
    std::set<std::string> topics;
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections())
      topics.insert(c->topic + " (" + c->datatype + ")");
    throw InvalidInputError(topic + ": no message on it in '" + selection.path + "' (its topics: " +
                            (topics.empty() ? std::string("none") : quotedList(topics)) + ")");
  }
  for (const rosbag::ConnectionInfo* c : view.getConnections())
  {
    if (c->datatype != kPoseStamped && c->datatype != kTransformStamped && c->datatype != kTfMessage)
      throw InvalidInputError(topic + ": carries " + c->datatype + "; expected " + kPoseStamped + ", " +
                              kTransformStamped + " or " + kTfMessage);
    if (!datatype->empty() && *datatype != c->datatype)
      throw InvalidInputError(topic + ": carries both " + *datatype + " and " + c->datatype);
    *datatype = c->datatype;
  }
  std::vector<StampedPose> poses;
  for (const rosbag::MessageInstance& m : view)
  {
    if (*datatype == kPoseStamped)
    {
      const auto msg = m.instantiate<geometry_msgs::PoseStamped>();
      const geometry_msgs::Point& p = msg->pose.position;
      const geometry_msgs::Quaternion& q = msg->pose.orientation;
      poses.push_back({ msg->header.frame_id, std::string(), msg->header.stamp,
                        Pose<double>(Quaternion<double>(q.w, q.x, q.y, q.z), Vector3<double>(p.x, p.y, p.z)) });
    }
    else if (*datatype == kTransformStamped)
    {
      poses.push_back(fromTransform(*m.instantiate<geometry_msgs::TransformStamped>()));
      children->insert(poses.back().child);
    }
    else
    {
      // Held here: a range over the member of a temporary pointer would outlive the message.
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      for (const geometry_msgs::TransformStamped& t : tf->transforms)
      {
        children->insert(t.child_frame_id);
        if (t.child_frame_id == selection.frame)
          poses.push_back(fromTransform(t));
      }
    }
  }
  return poses;
}

/// The poses of the selection's --frame and --parent (see readWaypointsBag).
std::vector<StampedPose> selectFrames(std::vector<StampedPose> poses, const BagSelection& selection,
                                      const std::string& datatype, const std::set<std::string>& children)
{
  const std::string where = "'" + selection.topic + "' of '" + selection.path + "'";
  if (!selection.frame.empty())
  {
    std::vector<StampedPose> of_frame;
    for (StampedPose& p : poses)
      if (p.child == selection.frame)
        of_frame.push_back(std::move(p));
    if (of_frame.empty())
      throw InvalidInputError("--frame '" + selection.frame + "': no transform of it in " + where +
                              " (its child frames: " + (children.empty() ? "none" : quotedList(children)) + ")");
    poses = std::move(of_frame);
  }
  const std::string what = datatype == kPoseStamped ? "poses on " + where : "transforms of '" + poses.front().child + "' in " + where;
  std::set<std::string> parents;
  for (const StampedPose& p : poses)
    parents.insert(p.parent);
  if (selection.parent.empty())
  {
    if (parents.size() > 1)
      throw InvalidInputError("--parent: the " + what + " are given in several frames (" + quotedList(parents) +
                              "); choose one with --parent");
    return poses;
  }
  if (parents.count(selection.parent) == 0)
    throw InvalidInputError("--parent '" + selection.parent + "': none of the " + what + " is given in it (their frames: " +
                            quotedList(parents) + ")");
  std::vector<StampedPose> in_parent;
  for (StampedPose& p : poses)
    if (p.parent == selection.parent)
      in_parent.push_back(std::move(p));
  return in_parent;
}
}  // namespace

RecordedWaypoints parseWaypointsCsv(std::string_view text, const std::string& path)
{
  RecordedWaypoints r;
  r.source = "--waypoints '" + path + "'";
  r.first_line = 2;
  const auto refuse = [&r](std::size_t line, const std::string& why) {
    throw InvalidInputError(r.source + " line " + std::to_string(line) + ": " + why);
  };
  if (text.empty())
    refuse(1, "the file is empty; expected a header naming the columns t,x,y,z,qx,qy,qz,qw");
  std::size_t end = text.find('\n');
  const std::vector<std::string_view> header = splitCells(text.substr(0, end));
  // role[c]: which of kWaypointColumns header cell c is, or kColumnCount for another column.
  std::vector<std::size_t> role(header.size(), kColumnCount);
  std::array<std::size_t, kColumnCount> column;
  column.fill(header.size());
  for (std::size_t c = 0; c < header.size(); ++c)
    for (std::size_t k = 0; k < kColumnCount; ++k)
      if (trimmed(header[c]) == kWaypointColumns[k])
      {
        if (column[k] != header.size())
          refuse(1, "column '" + std::string(kWaypointColumns[k]) + "' named twice (columns " +
                        std::to_string(column[k] + 1) + " and " + std::to_string(c + 1) + ")");
        column[k] = c;
        role[c] = k;
      }
  for (std::size_t k = 0; k < kColumnCount; ++k)
    if (column[k] == header.size())
      refuse(1, "column '" + std::string(kWaypointColumns[k]) +
                    "': missing from the header (t,x,y,z,qx,qy,qz,qw are found by name, in any order)");

  std::size_t line = 1;
  std::array<double, kColumnCount> v;
  while (end != std::string_view::npos && end + 1 < text.size())
  {
    ++line;
    const std::size_t start = end + 1;
    end = text.find('\n', start);
    std::string_view rest = text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
    const std::size_t cells = static_cast<std::size_t>(std::count(rest.begin(), rest.end(), ',')) + 1;
    if (cells != header.size())
      refuse(line, std::to_string(cells) + (cells == 1 ? " cell" : " cells") + ", but the header (line 1) has " +
                       std::to_string(header.size()));
    for (std::size_t c = 0;; ++c)
    {
      const std::size_t comma = rest.find(',');
      if (role[c] < kColumnCount)
      {
        const std::string_view cell = trimmed(rest.substr(0, comma));
        double& value = v[role[c]];
        const std::from_chars_result parsed = std::from_chars(cell.data(), cell.data() + cell.size(), value);
        if (parsed.ec != std::errc() || parsed.ptr != cell.data() + cell.size() || !std::isfinite(value))
          refuse(line, "column '" + std::string(kWaypointColumns[role[c]]) + "' (column " + std::to_string(c + 1) +
                           "): '" + std::string(cell.substr(0, 40)) + "' is not a finite number");
      }
      if (comma == std::string_view::npos)
        break;
      rest.remove_prefix(comma + 1);
    }
    r.times.push_back(v[0]);
    r.waypoints.emplace_back(Quaternion<double>(v[7], v[4], v[5], v[6]), Vector3<double>(v[1], v[2], v[3]));
  }
  if (r.waypoints.empty())
    refuse(2, "no rows after the header; expected one waypoint per line");
  return r;
}

RecordedWaypoints readWaypointsCsv(const std::string& path)
{
  return parseWaypointsCsv(readWholeFile(path, "--waypoints '" + path + "'"), path);
}

RecordedWaypoints readWaypointsBag(const BagSelection& selection)
{
  rosbag::Bag bag;
  try
  {
    bag.open(selection.path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    throw InvalidInputError("--bag '" + selection.path + "': cannot be opened: " + e.what());
  }
  std::string datatype;
  std::vector<StampedPose> poses;
  std::set<std::string> children;
  try
  {
    poses = readTopic(bag, selection, &datatype, &children);
  }
  catch (const ros::Exception& e)
  {
    throw InvalidInputError("--bag '" + selection.path + "': cannot be read: " + e.what());
  }
  if (datatype == kTfMessage && selection.frame.empty())
    throw InvalidInputError("--frame: --topic '" + selection.topic + "' carries " + kTfMessage +
                            "; choose the transforms by their child frame with --frame (its child frames: " +
                            (children.empty() ? "none" : quotedList(children)) + ")");
  if (datatype == kPoseStamped && !selection.frame.empty())
    throw InvalidInputError("--frame '" + selection.frame + "': --topic '" + selection.topic + "' carries " +
                            kPoseStamped + ", which has no child frame (--frame is for transforms)");
  poses = selectFrames(std::move(poses), selection, datatype, children);

  RecordedWaypoints r;
  r.source = "--bag '" + selection.path + "' --topic " + selection.topic;
  r.frame_id = poses.front().parent;
  const ros::Time origin = poses.front().stamp;
  r.time_origin_ns = static_cast<std::int64_t>(origin.toNSec());
  for (const StampedPose& p : poses)
  {
    r.waypoints.push_back(p.pose);
    r.times.push_back((p.stamp - origin).toSec());
  }
  return r;
}

std::string recordedOrigin(const RecordedWaypoints& recorded, std::size_t i)
{
  if (recorded.first_line > 0)
    return "line " + std::to_string(recorded.first_line + i) + " of " + recorded.source;
  return "pose " + std::to_string(i) + " of " + recorded.source;
}

std::string withRecordedOrigin(const std::string& message, const RecordedWaypoints& recorded)
{
  std::size_t best = std::string::npos;
  std::size_t index = 0;
  for (const char* field : { "waypoints[", "times[" })
  {
    const std::size_t at = message.find(field);
    if (at == std::string::npos || at >= best)
      continue;
    const char* const first = message.data() + at + std::strlen(field);
    std::size_t i = 0;
    const std::from_chars_result parsed = std::from_chars(first, message.data() + message.size(), i);
    if (parsed.ec == std::errc() && parsed.ptr < message.data() + message.size() && *parsed.ptr == ']' &&
        i < recorded.waypoints.size())
    {
      best = at;
      index = i;
    }
  }
  if (best == std::string::npos)
    return message;
  return message + " (waypoints[" + std::to_string(index) + "] and times[" + std::to_string(index) +
         "] come from " + recordedOrigin(recorded, index) + ")";
}

}  // namespace cli
}  // namespace se3_interpolation
