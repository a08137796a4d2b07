#include "recorded_waypoints.h"

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <set>
#include <system_error>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace cli
{
namespace
{
/// "'a', 'b'" of a set of names.
std::string quotedList(const std::set<std::string>& names)
{
  std::string list;
  for (const std::string& name : names)
    list += (list.empty() ? "'" : ", '") + name + "'";
  return list;
}

/// Whether the file at `path` starts as a bag of format 2.0 does (its version line), so that a
/// read error further on means a bag cut short, not another kind of file.
bool startsLikeABag(const std::string& path)
{
  static const char kVersionLine[] = "#ROSBAG V2.0\n";
  char start[sizeof kVersionLine - 1] = {};
  std::ifstream f(path, std::ios::binary);
  return f.read(start, sizeof start) && std::memcmp(start, kVersionLine, sizeof start) == 0;
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
    throw InvalidInputError(topic + ": no message on it in '" + selection.path +
                            "' (its topics: " + (topics.empty() ? std::string("none") : quotedList(topics)) + ")");
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
  const std::string what =
      datatype == kPoseStamped ? "poses on " + where : "transforms of '" + poses.front().child + "' in " + where;
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
    throw InvalidInputError("--parent '" + selection.parent + "': none of the " + what +
                            " is given in it (their frames: " + quotedList(parents) + ")");
  std::vector<StampedPose> in_parent;
  for (StampedPose& p : poses)
    if (p.parent == selection.parent)
      in_parent.push_back(std::move(p));
  return in_parent;
}
}  // namespace

RecordedWaypoints readWaypointsBag(const BagSelection& selection)
{
  rosbag::Bag bag;
  // A bag cut short (a recording killed, a copy interrupted) has no index at its end: rosbag says
  // "Bag unindexed" or, where the header points past the end, "wanted 4 bytes, read 0 bytes".
  const std::string cut_short =
      "; the bag looks cut short (a recording or a copy interrupted before its index was "
      "written): `rosbag reindex " +
      selection.path +
      "` rebuilds the index from the "
      "messages it holds";
  try
  {
    bag.open(selection.path, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagUnindexedException& e)
  {
    throw InvalidInputError("--bag '" + selection.path + "': cannot be opened: " + e.what() + cut_short);
  }
  catch (const rosbag::BagException& e)
  {
    const bool read_error = dynamic_cast<const rosbag::BagIOException*>(&e) != nullptr;
    throw InvalidInputError("--bag '" + selection.path + "': cannot be opened: " + e.what() +
                            (read_error && startsLikeABag(selection.path) ? cut_short : std::string()));
  }
  std::string datatype;
  std::vector<StampedPose> poses;
  std::set<std::string> children;
  try
  {
    poses = readTopic(bag, selection, &datatype, &children);
  }
  catch (const rosbag::BagIOException& e)
  {
    throw InvalidInputError("--bag '" + selection.path + "': cannot be read: " + e.what() + cut_short);
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
    return "line " + std::to_string(recorded.first_line + i) + ", column 1 (byte offset " +
           std::to_string(i < recorded.line_offsets.size() ? recorded.line_offsets[i] : 0) + ") of " + recorded.source;
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
  return message + " (waypoints[" + std::to_string(index) + "] and times[" + std::to_string(index) + "] come from " +
         recordedOrigin(recorded, index) + ")";
}

}  // namespace cli
}  // namespace se3_interpolation
