#include "se3_interpolation/ros/interpolation_node.h"

#include <malloc.h>

#include <chrono>
#include <new>
#include <sstream>

#include "se3_interpolation/GenerationStatus.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/ros/conversions.h"

namespace se3_interpolation
{
namespace
{
/// Allocations from this size up are mapped and unmapped on their own (returned to the system
/// when freed): glibc's default raises this threshold after each large free, after which large
/// messages stay in the heap.
constexpr int kMmapThreshold = 128 * 1024;
/// glibc's malloc arenas, at most (by default one per allocating thread, each keeping its own
/// freed pages after a large publication): the node's threads share these, reusing what one frees.
constexpr int kArenaMax = 2;

Nanoseconds toNanoseconds(const ros::Time& t)
{
  return static_cast<Nanoseconds>(t.toNSec());
}
}  // namespace

InterpolationNode::InterpolationNode(ros::NodeHandle nh, ros::NodeHandle private_nh)
  : nh_(std::move(nh))
  , private_nh_(std::move(private_nh))
  , start_params_(loadNodeParameters(private_nh_))
  , tf_listener_(tf_buffer_)
{
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
  mallopt(M_ARENA_MAX, kArenaMax);
  const NodeParameters& p = start_params_;
  playback_.setLoop(p.loop);
  path_pub_ = private_nh_.advertise<nav_msgs::Path>("path", 1, true);
  trajectory_pub_ = private_nh_.advertise<trajectory_msgs::MultiDOFJointTrajectory>("trajectory", 1, true);
  markers_pub_ = private_nh_.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  status_pub_ = private_nh_.advertise<GenerationStatus>("status", 1, true);
  moving_frame_ = std::make_unique<MovingFrame>(nh_, private_nh_, playback_, p.publish_tf, p.tf_rate, p.child_frame_id);
  arm_ = std::make_unique<NodeArm>(nh_, private_nh_, p);
  parameters_ = std::make_unique<RunTimeParameters>(
      private_nh_, p, [this](const NodeParameters& before, const NodeParameters& after) {
        playback_.setLoop(after.loop);
        if (after.tf_rate != before.tf_rate)
          moving_frame_->setRate(after.tf_rate);
        if (follow_server_ &&
            (after.command_rate != before.command_rate || after.feedback_rate != before.feedback_rate))
          follow_server_->setRates(after.command_rate, after.feedback_rate);
        ROS_INFO_STREAM("dynamic_reconfigure: curve " << after.curve << ", geometry " << after.geometry
                                                      << ", parameterization " << after.parameterization << ", timing "
                                                      << after.timing << ", loop " << (after.loop ? "on" : "off")
                                                      << ", tf_rate " << after.tf_rate << " Hz");
      });
  follow_server_ = std::make_unique<FollowTrajectoryServer>(
      private_nh_, playback_, tf_buffer_, [this] { return parameters_->get(); }, publish_mutex_, p);
  waypoint_topics_ = std::make_unique<WaypointTopics>(private_nh_, p, tf_buffer_, [this] { autoGenerate(); });
  clear_service_ = private_nh_.advertiseService("clear_waypoints", &InterpolationNode::clearWaypoints, this);
  ros::NodeHandle service_nh(private_nh_);
  service_nh.setCallbackQueue(&service_queue_);
  generate_service_ = service_nh.advertiseService("generate", &InterpolationNode::generate, this);
  service_spinner_ = std::make_unique<ros::AsyncSpinner>(p.service_threads, &service_queue_);
  service_spinner_->start();

  if (p.master_check_period > 0.0)
    watchdog_ = std::make_unique<MasterWatchdog>(private_nh_, p.master_check_period,
                                                 std::vector<std::string>{ generate_service_.getService(),
                                                                           clear_service_.getService(),
                                                                           private_nh_.resolveName("set_parameters") },
                                                 [this] { writeNodeParameters(private_nh_, parameters_->get()); });
  ros::NodeHandle maintenance_nh(private_nh_);
  maintenance_nh.setCallbackQueue(&maintenance_queue_);
  maintenance_timer_ =
      maintenance_nh.createWallTimer(ros::WallDuration(1.0), &InterpolationNode::maintenanceCallback, this);
  maintenance_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &maintenance_queue_);
  maintenance_spinner_->start();
  ROS_INFO_STREAM("se3_interpolation_node ready: services "
                  << generate_service_.getService() << ", " << clear_service_.getService() << "; waypoints on "
                  << waypoint_topics_->waypointTopic() << ", " << waypoint_topics_->waypointsTopic() << "; frames "
                  << p.frame_id << " -> " << p.child_frame_id << (p.publish_tf ? "" : " (TF off)") << " at "
                  << p.tf_rate << " Hz" << (p.loop ? " looping" : "") << ", " << p.max_tf_samples
                  << " static; defaults curve " << p.curve << ", geometry " << p.geometry << ", parameterization "
                  << p.parameterization << "; auto_generate " << (p.auto_generate ? "on" : "off") << "; max_samples "
                  << p.max_samples << ", max_waypoints " << p.max_waypoints << "; " << arm_->summary());
}

InterpolationNode::~InterpolationNode()
{
  // Every thread that calls into the parts stops before the parts go.
  service_spinner_->stop();
  maintenance_spinner_->stop();
  watchdog_.reset();
  waypoint_topics_.reset();
  follow_server_.reset();
  parameters_.reset();
  moving_frame_.reset();
}

bool InterpolationNode::generate(GenerateTrajectory::Request& req, GenerateTrajectory::Response& res)
{
  generateInto(req, res);
  publishStatus(req, res, "service");
  return true;  // errors travel in res.success / res.message (a false return loses them)
}

InterpolationNode::Waypoints InterpolationNode::gatherWaypoints(const GenerateTrajectory::Request& req,
                                                                const NodeParameters& params) const
{
  Waypoints w;
  if (req.waypoints.poses.empty() && req.waypoint_frames.empty())
  {
    WaypointTopics::Buffer::Snapshot buffered = waypoint_topics_->buffer().snapshot();
    w.recorded_times = buffered.recordedTimes();
    w.poses = std::move(buffered.waypoints);
    w.frame = buffered.frame_id;
    if (w.poses.size() < 2)
      throw InvalidInputError("waypoints: 0 given and the ~waypoint buffer " +
                              (w.poses.empty() ? std::string("is empty") : "holds only 1") + "; at least 2 are needed");
  }
  else
  {
    w.poses = req.waypoints.poses;
    w.frame = req.waypoints.header.frame_id.empty() ? params.frame_id : req.waypoints.header.frame_id;
  }
  validateFrameId(w.frame, "waypoints.header.frame_id");
  if (!req.waypoint_frames.empty())
  {
    const std::size_t max_waypoints = params.limits().max_waypoints;
    if (w.poses.size() + req.waypoint_frames.size() > max_waypoints)
      throw LimitExceededError(
          "waypoints: " + std::to_string(w.poses.size()) + " poses and " + std::to_string(req.waypoint_frames.size()) +
          " waypoint_frames given; the limit (~max_waypoints) is " + std::to_string(max_waypoints));
    const std::vector<geometry_msgs::Pose> taught =
        lookUpWaypointFrames(req.waypoint_frames, w.frame, params.tf_timeout);
    w.poses.insert(w.poses.end(), taught.begin(), taught.end());
  }
  return w;
}

ros::Time InterpolationNode::startOf(const GenerateTrajectory::Request& req, const NodeParameters& params,
                                     const std::string& frame, const std::string& child,
                                     std::vector<double>* recorded_times, TrajectoryRequest* r) const
{
  ros::Time stamp = req.waypoints.header.stamp;
  // A fit of the buffer without times: the poses streamed on ~waypoint are a recording, timed by
  // their stamps (after the first one's). It is replayed from its first pose, at its own pace:
  // the recording is the motion, so it does not replan from the current one (from_current).
  bool from_current = req.from_current;
  if (r->curve == FitFamily::kName && r->times.empty() && !recorded_times->empty())
  {
    r->times = std::move(*recorded_times);
    from_current = false;
  }
  if (from_current)
  {
    // The switch time T_s: the request's stamp, else ~replan_lead from now; times count from it.
    if (stamp.isZero())
      stamp = ros::Time::now() + ros::Duration(params.replan_lead);
    startFromCurrent(stamp, frame, child, r);
  }
  return stamp;
}

void InterpolationNode::generateInto(const GenerateTrajectory::Request& req, GenerateTrajectory::Response& res)
{
  std::vector<std::string> filled;  // the request fields taken from the node's parameters
  try
  {
    const NodeParameters params = parameters_->get();
    const PlannerLimits limits = params.limits();
    Waypoints waypoints = gatherWaypoints(req, params);
    const std::vector<geometry_msgs::Pose>& poses = waypoints.poses;
    const std::string& frame = waypoints.frame;
    std::vector<double>& recorded_times = waypoints.recorded_times;
    const std::string child = req.child_frame_id.empty() ? params.child_frame_id : req.child_frame_id;
    validateFrameId(child, "child_frame_id");
    if (child == frame)
      throw InvalidInputError("child_frame_id: " + quotedText(child) + " is also the waypoints' frame");

    const ResponseOutputs outputs = parseResponseOutputs(req.outputs);
    TrajectoryRequest r = fromMsg(req, poses);
    filled = applyRequestDefaults(params, &r);
    ros::Time stamp = startOf(req, params, frame, child, &recorded_times, &r);
    const std::chrono::steady_clock::time_point planning = std::chrono::steady_clock::now();
    const TrajectoryResult result = se3_interpolation::generate(r, limits, arm_->forRequest());
    const std::chrono::steady_clock::time_point filling = std::chrono::steady_clock::now();

    std_msgs::Header header;
    header.frame_id = frame;
    header.stamp = stamp.isZero() ? ros::Time::now() : stamp;
    validateStampedSpan(header.stamp.toSec(), result.start_time, result.start_time + result.duration,
                        "waypoints.header.stamp");

    if (outputs.path)
      toMsg(result, header, res.path);
    if (outputs.trajectory)
      toMsg(result, header, child, res.trajectory);
    // (Without an arm the joint trajectory stays empty, its header unset, as an omitted output.)
    if (outputs.joint_trajectory && !result.joint_names.empty())
      toMsg(result, header, res.joint_trajectory);
    // The service's latency apart from transport (docs/performance.md "Service latency"):
    // rosconsole logger ros.se3_interpolation.timing at debug level.
    ROS_DEBUG_NAMED("timing", "generate: %zu samples, planner %.1f ms, response messages %.1f ms",
                    result.samples.size(), 1e3 * std::chrono::duration<double>(filling - planning).count(),
                    1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - filling).count());
    copyFigures(result, res);
    copyFit(result, header, res);
    res.success = true;
    res.message = generationMessage(r, result);
    if (req.publish)
    {
      // The topics carry both forms whatever the response omits.
      nav_msgs::Path path;
      trajectory_msgs::MultiDOFJointTrajectory trajectory;
      if (!publish(result, outputs.path ? res.path : toMsg(result, header, path),
                   outputs.trajectory ? res.trajectory : toMsg(result, header, child, trajectory), header, child,
                   params))
        res.message +=
            "; published, but not played on the moving frame: it executes ~follow_trajectory goals "
            "(the setpoint ~command), which alone move it";
    }
  }
  catch (const std::bad_alloc&)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = "out of memory while generating the trajectory (reduce sample_count or the waypoints)";
  }
  catch (const std::exception& e)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = boundedMessage(namingParameters(withLimitPrefix(e.what(), "~"), filled));
  }
  catch (...)
  {
    res = GenerateTrajectory::Response();
    res.success = false;
    res.message = "unexpected error while generating the trajectory";
  }
}

std::vector<std::string> InterpolationNode::applyRequestDefaults(const NodeParameters& params,
                                                                 TrajectoryRequest* request)
{
  TrajectoryRequest& r = *request;
  std::vector<std::string> filled;
  auto fill = [&filled](auto* field, const auto& value, bool empty, const char* name) {
    if (!empty || *field == value)
      return;
    *field = value;
    filled.push_back(name);
  };
  fill(&r.curve, params.curve, r.curve.empty(), "curve");
  // The node's default radius applies to the curve that uses it only (never an error elsewhere).
  fill(&r.blend_radius, params.blend_radius, r.blend_radius == 0.0 && r.curve == "piecewise_geodesic", "blend_radius");
  fill(&r.geometry, params.geometry, r.geometry.empty(), "geometry");
  fill(&r.parameterization, params.parameterization, r.parameterization.empty(), "parameterization");
  fill(&r.timing, params.timing, r.timing.empty(), "timing");
  fill(&r.max_linear_velocity, params.max_linear_velocity, r.max_linear_velocity == 0.0, "max_linear_velocity");
  fill(&r.max_angular_velocity, params.max_angular_velocity, r.max_angular_velocity == 0.0, "max_angular_velocity");
  fill(&r.max_linear_acceleration, params.max_linear_acceleration, r.max_linear_acceleration == 0.0,
       "max_linear_acceleration");
  fill(&r.max_angular_acceleration, params.max_angular_acceleration, r.max_angular_acceleration == 0.0,
       "max_angular_acceleration");
  fill(&r.max_linear_jerk, params.max_linear_jerk, r.max_linear_jerk == 0.0, "max_linear_jerk");
  fill(&r.max_angular_jerk, params.max_angular_jerk, r.max_angular_jerk == 0.0, "max_angular_jerk");
  fill(&r.speed, params.speed, r.speed == 0.0, "speed");
  // The fit's defaults apply to the curve that uses them only (never an error elsewhere).
  const bool fit = r.curve == FitFamily::kName;
  fill(&r.control_period, params.control_period, fit && r.control_period == 0.0, "control_period");
  fill(&r.smoothing, params.smoothing, fit && r.smoothing == 0.0, "smoothing");
  fill(&r.loss, params.loss, fit && r.loss.empty(), "loss");
  fill(&r.loss_scale, params.loss_scale, fit && r.loss_scale == 0.0, "loss_scale");
  fill(&r.duration, params.duration, r.duration == 0.0, "duration");
  fill(&r.sample_count, static_cast<std::uint32_t>(params.sample_count),
       r.sample_count == 0 && r.sample_times.empty() && r.sample_period == 0.0, "sample_count");
  fill(&r.sample_tolerance, params.sample_tolerance, r.sample_tolerance == 0.0, "sample_tolerance");
  return filled;
}

std::string InterpolationNode::namingParameters(const std::string& message, const std::vector<std::string>& filled)
{
  // The core names the request's field; where the node filled it from its parameter of the same
  // name, that parameter is what the user has to change.
  for (const std::string& name : filled)
    if (message.compare(0, name.size() + 1, name + ":") == 0)
      return "~" + message + " (the node's parameter, used for the request's empty " + name + ")";
  return message;
}

std::vector<geometry_msgs::Pose> InterpolationNode::lookUpWaypointFrames(const std::vector<std::string>& frames,
                                                                         const std::string& target,
                                                                         double timeout) const
{
  std::vector<geometry_msgs::Pose> poses;
  poses.reserve(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
  {
    const std::string field = indexedField("waypoint_frames", i);
    validateFrameId(frames[i], field);
    geometry_msgs::TransformStamped t;
    try
    {
      // The latest transform; tf2's listener thread fills the buffer while this one waits.
      t = tf_buffer_.lookupTransform(target, frames[i], ros::Time(0), ros::Duration(timeout));
    }
    catch (const tf2::TransformException& e)
    {
      std::ostringstream why;
      why << field << ": no transform from " << quotedText(frames[i]) << " to " << quotedText(target)
          << " within ~tf_timeout = " << timeout << " s (tf2: " << boundedMessage(e.what()) << ")";
      throw InvalidInputError(why.str());
    }
    poses.push_back(toMsg(fromMsg(t.transform)));
  }
  return poses;
}

bool InterpolationNode::publish(const TrajectoryResult& result, const nav_msgs::Path& path,
                                const trajectory_msgs::MultiDOFJointTrajectory& trajectory,
                                const std_msgs::Header& header, const std::string& child_frame_id,
                                const NodeParameters& params)
{
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  path_pub_.publish(path);
  trajectory_pub_.publish(trajectory);
  markers_pub_.publish(toMarkerArray(result, result.waypoints, header, params.marker_axes, params.axis_length));
  moving_frame_->publishSamples(result, header, child_frame_id, params.max_tf_samples);
  if (follow_server_->ownsFrame())
    return false;
  Motion motion;
  motion.state_at = result.state_at;
  motion.start_time = result.start_time;
  motion.duration = result.duration;
  motion.frame_id = header.frame_id;
  motion.child_frame_id = child_frame_id;
  motion.tag = "~generate";
  playback_.play(std::move(motion), toNanoseconds(header.stamp), toNanoseconds(ros::Time::now()));
  return true;
}

void InterpolationNode::publishStatus(const GenerateTrajectory::Request& req, const GenerateTrajectory::Response& res,
                                      const std::string& source)
{
  const NodeParameters params = parameters_->get();
  GenerationStatus status;
  status.header.stamp = ros::Time::now();
  status.success = res.success;
  status.message = res.message;
  status.source = source;
  // The request's strings may be anything (a refused 10 MB name): the latched status carries
  // them only when they are short names, else their quoted prefix.
  auto bounded = [](const std::string& text) { return text.size() <= kMaxFrameIdLength ? text : quotedText(text); };
  status.curve = bounded(req.curve.empty() ? params.curve : req.curve);
  status.geometry = bounded(req.geometry.empty() ? params.geometry : req.geometry);
  status.timing = bounded(req.timing.empty() ? params.timing : req.timing);
  if (req.waypoints.poses.empty() && req.waypoint_frames.empty())
  {
    const WaypointTopics::Buffer& buffer = waypoint_topics_->buffer();
    status.header.frame_id = buffer.frameId();
    status.waypoint_count = static_cast<std::uint32_t>(buffer.size());
  }
  else
  {
    status.header.frame_id =
        bounded(req.waypoints.header.frame_id.empty() ? params.frame_id : req.waypoints.header.frame_id);
    status.waypoint_count = static_cast<std::uint32_t>(req.waypoints.poses.size() + req.waypoint_frames.size());
  }
  copyFigures(res, status);
  status.dropped_waypoint_messages = waypoint_topics_->droppedWaypoint();
  status.dropped_waypoints_messages = waypoint_topics_->droppedWaypoints();
  status_pub_.publish(status);
}

bool InterpolationNode::clearWaypoints(std_srvs::Trigger::Request& /*req*/, std_srvs::Trigger::Response& res)
{
  const WaypointTopics::Buffer::Snapshot cleared = waypoint_topics_->buffer().clear();
  {
    std::lock_guard<std::mutex> publishing(publish_mutex_);
    follow_server_->interrupt("~clear_waypoints stopped the motion");
    // Brought to rest along its path within the bounds, as a cancel is: a hold would stop the
    // frame (and ~command) within one step.
    playback_.stop(stopStart(toNanoseconds(ros::Time::now())), stopLimitsOf(parameters_->get()));
    nav_msgs::Path empty;
    empty.header.stamp = ros::Time::now();
    empty.header.frame_id = cleared.frame_id;
    path_pub_.publish(empty);
    visualization_msgs::MarkerArray deletion;
    visualization_msgs::Marker all;
    all.header = empty.header;
    all.action = visualization_msgs::Marker::DELETEALL;
    deletion.markers.push_back(all);
    markers_pub_.publish(deletion);
  }
  res.success = true;
  res.message = "cleared " + std::to_string(cleared.waypoints.size()) +
                " waypoints; the frame stops along its path, path and markers cleared";
  return true;
}

void InterpolationNode::autoGenerate()
{
  const NodeParameters params = parameters_->get();
  if (!params.auto_generate)
    return;
  GenerateTrajectory::Request req;
  req.publish = true;
  req.from_current = params.replan_from_current;
  GenerateTrajectory::Response res;
  generateInto(req, res);
  publishStatus(req, res, "auto_generation");
  if (res.success)
    ROS_INFO_STREAM("auto-generated: " << res.message);
  else
    ROS_WARN_STREAM("auto-generation failed: " << res.message);
}

void InterpolationNode::startFromCurrent(const ros::Time& switch_time, const std::string& frame,
                                         const std::string& child, TrajectoryRequest* r) const
{
  const std::optional<PlaybackState> shown = playback_.at(toNanoseconds(switch_time));
  if (!shown || shown->child_frame_id != child)
    return;  // nothing plays on this frame: the trajectory starts at waypoints[0]
  if (shown->frame_id != frame)
    throw InvalidInputError("from_current: the moving frame " + quotedText(child) + " plays in frame " +
                            quotedText(shown->frame_id) + ", not in the waypoints' frame " + quotedText(frame) +
                            " (give waypoints in that frame, or from_current false)");
  StartState start;
  start.pose = shown->sample.pose;
  start.velocity = shown->sample.velocity;  // zero where the frame is held
  start.acceleration = shown->sample.acceleration;
  r->start_state = start;
}

void InterpolationNode::maintenanceCallback(const ros::WallTimerEvent& /*event*/)
{
  waypoint_topics_->reportDrops();
  // Large messages (floods, 1e5-sample trajectories and their serialised copies) are freed on
  // many threads; glibc keeps the freed pages unless asked.
  malloc_trim(0);
}

}  // namespace se3_interpolation
