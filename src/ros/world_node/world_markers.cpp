#include "swarm_forage/ros/world_node/world_markers.hpp"

#include <swarm_forage/CommandBatch.h>

#include <string>

namespace swarm_forage {

namespace {
std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(double x, double y, double z = 0) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

// Walls, nest, lights, cubes, ramps, cache area and count, one marker per robot class and one per task.
constexpr std::size_t kMarkers = 7 + static_cast<std::size_t>(RobotClass::kCount) + kTasksShown;

/// Marker k of `out` (already sized) set up afresh as (ns, id, type), its points' storage kept for reuse.
visualization_msgs::Marker& slot(visualization_msgs::MarkerArray& out, std::size_t k, const char* ns, int id,
                                 int type, const ros::Time& stamp) {
  visualization_msgs::Marker& m = out.markers[k];
  m.header.frame_id = "map";
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1;
  m.pose.position = point(0, 0);
  m.points.clear();
  m.colors.clear();
  m.text.clear();
  return m;
}
}  // namespace

RobotClass robotClass(const SensorData& s, uint32_t i) {
  if (s.carried_block[i] >= 0) return RobotClass::kCarrying;
  if (s.threatened[i]) return RobotClass::kAvoiding;
  if (s.ground[i] == kNest) return RobotClass::kInNest;
  return RobotClass::kExploring;
}

std_msgs::ColorRGBA robotClassColour(RobotClass c) {
  switch (c) {
    case RobotClass::kCarrying:
      return rgba(1.f, 0.55f, 0.f);
    case RobotClass::kAvoiding:
      return rgba(0.9f, 0.1f, 0.1f);
    case RobotClass::kInNest:
      return rgba(0.1f, 0.8f, 0.2f);
    default:
      return rgba(0.4f, 0.7f, 1.f);
  }
}

std_msgs::ColorRGBA taskColour(uint8_t task) {
  switch (task) {
    case CommandBatch::TASK_GENERALIST:
      return rgba(1.f, 1.f, 1.f);
    case CommandBatch::TASK_HARVESTER:
      return rgba(0.85f, 0.1f, 0.6f);
    default:  // CommandBatch::TASK_COLLECTOR
      return rgba(0.1f, 0.2f, 0.8f);
  }
}

namespace {
using visualization_msgs::Marker;
using visualization_msgs::MarkerArray;

// The walls, the nest and the lights, from marker k on.
void paintArena(const ArenaConfig& a, const ros::Time& stamp, MarkerArray& out, std::size_t& k) {
  Marker& walls = slot(out, k++, "arena", 0, Marker::LINE_STRIP, stamp);
  walls.scale.x = 0.1;
  walls.color = rgba(0.3f, 0.3f, 0.3f);
  for (const auto& c :
       {point(0, 0), point(a.width, 0), point(a.width, a.height), point(0, a.height), point(0, 0)})
    walls.points.push_back(c);

  const Rect n = a.nest();
  Marker& nest = slot(out, k++, "nest", 0, Marker::CUBE, stamp);
  nest.pose.position = point((n.min_x + n.max_x) / 2, (n.min_y + n.max_y) / 2, -0.01);
  nest.scale.x = n.width();
  nest.scale.y = n.height();
  nest.scale.z = 0.01;
  nest.color = rgba(0.55f, 0.85f, 0.55f, 0.6f);

  Marker& lights = slot(out, k++, "lights", 0, Marker::SPHERE_LIST, stamp);
  lights.scale.x = lights.scale.y = lights.scale.z = 0.4;
  lights.color = rgba(1.f, 0.95f, 0.2f);
  for (int l = 0; l < ArenaConfig::kLights; ++l)
    lights.points.push_back(point(a.light(l).x(), a.light(l).y(), 0.2));
}

// Free blocks at their true sizes: cubes dark grey, ramps brown (CUBE_LIST: one size per marker).
void paintBlocks(const World& world, const ros::Time& stamp, MarkerArray& out, std::size_t& k) {
  const ArenaConfig& a = world.config().arena;
  const BlockField& blocks = world.blocks();
  Marker& cubes = slot(out, k++, "blocks", kCube, Marker::CUBE_LIST, stamp);
  cubes.scale.x = cubes.scale.y = cubes.scale.z = a.cube_size;
  cubes.color = rgba(0.25f, 0.25f, 0.3f);
  Marker& ramps = slot(out, k++, "blocks", kRamp, Marker::CUBE_LIST, stamp);
  ramps.scale.x = a.ramp_length;
  ramps.scale.y = ramps.scale.z = a.cube_size;
  ramps.color = rgba(0.6f, 0.4f, 0.2f);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto id = static_cast<int32_t>(b);
    if (blocks.carrier(id) != kFree) continue;
    (blocks.kind(id) == kRamp ? ramps : cubes)
        .points.push_back(point(blocks.x(id), blocks.y(id), a.cube_size / 2));
  }
}

// The static cache's area and its count of blocks; both deleted while there is no cache.
void paintCache(const StaticCache& cache, const ros::Time& stamp, MarkerArray& out, std::size_t& k) {
  Marker& area = slot(out, k++, "cache", 0, Marker::CUBE, stamp);
  Marker& count = slot(out, k++, "cache", 1, Marker::TEXT_VIEW_FACING, stamp);
  if (cache.exists()) {
    area.pose.position = point(cache.center().x(), cache.center().y(), -0.005);
    area.scale.x = cache.area().width();
    area.scale.y = cache.area().height();
    area.scale.z = 0.01;
    area.color = rgba(0.6f, 0.4f, 0.9f, 0.5f);
    count.pose.position = point(cache.center().x(), cache.center().y(), 1.0);
    count.scale.z = 1.0;
    count.color = rgba(0.2f, 0.1f, 0.4f);
    count.text = "cache: " + std::to_string(cache.size()) + " blocks";
  } else {
    area.action = count.action = Marker::DELETE;
  }
}

// Population dynamics: robots awaiting repair grey where they stopped (ns "robots", id 4; returned), and a
// text above the arena giving the counts and the repair queue, head first.
Marker& paintPopulation(const World& world, std::size_t robots, double r, const ros::Time& stamp,
                        MarkerArray& out, std::size_t& k) {
  const ArenaConfig& a = world.config().arena;
  Marker& repairing =
      slot(out, k++, "robots", static_cast<int>(RobotClass::kCount), Marker::SPHERE_LIST, stamp);
  repairing.scale.x = repairing.scale.y = repairing.scale.z = 2 * r;
  repairing.color = rgba(0.55f, 0.55f, 0.55f, 0.6f);
  const PopulationEvents& e = world.population().events();
  Marker& text = slot(out, k++, "population", 0, Marker::TEXT_VIEW_FACING, stamp);
  text.pose.position = point(a.width / 2, a.height + 1.0, 1.0);
  text.scale.z = 0.8;
  text.color = rgba(0.2f, 0.2f, 0.2f);
  text.text = "active " + std::to_string(e.active) + " of " + std::to_string(robots) + ", repair queue " +
              std::to_string(e.queue);
  std::size_t shown = 0;
  for (const uint32_t id : world.population().repairQueue()) {
    if (shown++ == 10) {
      text.text += " ...";
      break;
    }
    text.text += (shown == 1 ? ": " : ", ") + std::to_string(id);
  }
  return repairing;
}

// Robots: one SPHERE_LIST per class; with population dynamics the dead hidden and those awaiting repair
// apart.
void paintRobots(const World& world, const SensorData& s, const ros::Time& stamp, MarkerArray& out,
                 std::size_t& k) {
  const double r = world.config().robot.radius;
  const bool population = world.population().enabled();
  Marker* classes[static_cast<int>(RobotClass::kCount)];
  for (int c = 0; c < static_cast<int>(RobotClass::kCount); ++c) {
    Marker& m = slot(out, k++, "robots", c, Marker::SPHERE_LIST, stamp);
    m.scale.x = m.scale.y = m.scale.z = 2 * r;
    m.color = robotClassColour(static_cast<RobotClass>(c));
    classes[c] = &m;
  }
  Marker* repairing = population ? &paintPopulation(world, s.size(), r, stamp, out, k) : nullptr;
  for (uint32_t i = 0; i < s.size(); ++i) {
    if (population && world.population().presence(i) != Presence::kActive) {
      if (world.population().presence(i) == Presence::kRepair)
        repairing->points.push_back(point(s.x[i], s.y[i], r));
      continue;
    }
    classes[static_cast<int>(robotClass(s, i))]->points.push_back(point(s.x[i], s.y[i], r));
  }
}

// GP-DPO's tasks: a square of the task's colour on top of each robot's state colour.
void paintTasks(const SensorData& s, const CommandData& commands, double r, const ros::Time& stamp,
                MarkerArray& out, std::size_t& k) {
  Marker* tasks[kTasksShown];
  for (uint8_t t = 0; t < kTasksShown; ++t) {
    Marker& m = slot(out, k++, "tasks", t, Marker::CUBE_LIST, stamp);
    m.scale.x = m.scale.y = r;
    m.scale.z = 0.01;
    m.color = taskColour(t);
    tasks[t] = &m;
  }
  for (uint32_t i = 0; i < s.size() && i < commands.task.size(); ++i)
    if (commands.task[i] < kTasksShown)
      tasks[commands.task[i]]->points.push_back(point(s.x[i], s.y[i], 2.05 * r));
}
}  // namespace

void paintMarkers(const World& world, const SensorData& s, const CommandData& commands,
                  const ros::Time& stamp, MarkerArray& out) {
  const bool population = world.population().enabled();  // two markers more: the queue's robots and text
  out.markers.resize(kMarkers + (population ? 2 : 0));   // before any reference into it is taken
  std::size_t k = 0;
  paintArena(world.config().arena, stamp, out, k);
  paintBlocks(world, stamp, out, k);
  paintCache(world.cache(), stamp, out, k);
  paintRobots(world, s, stamp, out, k);
  paintTasks(s, commands, world.config().robot.radius, stamp, out, k);
  // rviz refuses a list marker without points ("Points should not be empty"): such a class is deleted.
  for (Marker& m : out.markers)
    if (m.type == Marker::CUBE_LIST || m.type == Marker::SPHERE_LIST)
      if (m.points.empty()) m.action = Marker::DELETE;
}

MarkerPublisher::MarkerPublisher(ros::NodeHandle& nh, double rate)
    : pub_(nh.advertise<visualization_msgs::MarkerArray>("world/markers", 1)), rate_(rate) {}

void MarkerPublisher::publish(const World& world, const SensorData& sensors, const CommandData& commands,
                              const ros::Time& stamp) {
  if (rate_ <= 0 || pub_.getNumSubscribers() == 0) return;  // nothing is built for nobody
  const ros::WallTime now = ros::WallTime::now();
  if (!last_.isZero() && (now - last_).toSec() < 1.0 / rate_) return;
  last_ = now;
  paintMarkers(world, sensors, commands, stamp, markers_);
  pub_.publish(markers_);
  ++built_;
  seconds_ = (ros::WallTime::now() - now).toSec();
}

}  // namespace swarm_forage
