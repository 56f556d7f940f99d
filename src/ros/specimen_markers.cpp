#include "virtual_triaxial/ros/specimen_markers.h"

#include <algorithm>
#include <numeric>
#include <vector>

namespace vt::ros {

namespace {

geometry_msgs::Point point(const dem::Vec3& v) {
  geometry_msgs::Point p;
  p.x = v.x;
  p.y = v.y;
  p.z = v.z;
  return p;
}

std_msgs::ColorRGBA color(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

visualization_msgs::Marker base(const std::string& ns, int id, int type, const std::string& frame,
                                const ::ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.frame_locked = true;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray to_marker_array(const dem::SpecimenSnapshot& s, const MarkerOptions& o,
                                                const ::ros::Time& stamp) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header.frame_id = o.frame;
  clear.header.stamp = stamp;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);

  const std::size_t n = s.position.size();
  const std::size_t every = o.max_particles > 0 && n > o.max_particles ? (n + o.max_particles - 1) / o.max_particles : 1;
  out.markers.reserve(n / every + 4);
  for (std::size_t i = 0; i < n; i += every) {
    visualization_msgs::Marker m =
        base("particles", static_cast<int>(i), visualization_msgs::Marker::SPHERE, o.frame, stamp);
    m.pose.position = point(s.position[i]);
    const dem::Quaternion& q = s.orientation[i];
    m.pose.orientation.w = q.w;
    m.pose.orientation.x = q.x;
    m.pose.orientation.y = q.y;
    m.pose.orientation.z = q.z;
    m.scale.x = 2.0 * s.semi_axes[i].x;
    m.scale.y = 2.0 * s.semi_axes[i].y;
    m.scale.z = 2.0 * s.semi_axes[i].z;
    m.color = s.idle[i] ? color(0.96f, 0.64f, 0.35f) : color(0.7f, 0.7f, 0.72f);
    out.markers.push_back(m);
  }

  visualization_msgs::Marker cell = base("cell", 0, visualization_msgs::Marker::LINE_LIST, o.frame, stamp);
  double r_mean = 0.0;
  for (double r : s.radius) r_mean += r;
  r_mean = n > 0 ? r_mean / static_cast<double>(n) : 0.0;
  cell.scale.x = 0.1 * r_mean;
  cell.color = color(0.2f, 0.4f, 0.9f);
  for (int k = 0; k < 8; ++k)
    for (int bit = 0; bit < 3; ++bit) {
      if (k & (1 << bit)) continue;
      const int l = k | (1 << bit);
      cell.points.push_back(point(s.h * dem::Vec3{double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)}));
      cell.points.push_back(point(s.h * dem::Vec3{double(l & 1), double((l >> 1) & 1), double((l >> 2) & 1)}));
    }
  out.markers.push_back(cell);

  if (o.strongest_contacts > 0 && !s.contacts.empty()) {
    std::vector<std::size_t> order(s.contacts.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const std::size_t k = std::min(o.strongest_contacts, order.size());
    const auto fn = [&](std::size_t c) { return norm(s.contacts[c].normal_force); };
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t a, std::size_t b) { return fn(a) > fn(b); });
    visualization_msgs::Marker f = base("forces", 0, visualization_msgs::Marker::LINE_LIST, o.frame, stamp);
    f.scale.x = 0.25 * r_mean;
    f.color = color(1.0f, 0.0f, 0.0f);
    const double fmax = fn(order[0]);
    for (std::size_t r = 0; r < k; ++r) {
      const dem::SnapshotContact& c = s.contacts[order[r]];
      const dem::Vec3& xi = s.position[static_cast<std::size_t>(c.i)];
      f.points.push_back(point(xi));
      f.points.push_back(point(xi + c.branch));
      const float t = fmax > 0.0 ? static_cast<float>(fn(order[r]) / fmax) : 1.0f;
      f.colors.push_back(color(t, 0.1f, 1.0f - t));
      f.colors.push_back(color(t, 0.1f, 1.0f - t));
    }
    out.markers.push_back(f);
  }
  return out;
}

}  // namespace vt::ros
