// The specimen as RViz markers (visualization_msgs/MarkerArray), in the cell
// frame (x = H s, origin at the cell corner; frame_id MarkerOptions::frame):
//   ns "particles"  one SPHERE marker per particle (id = storage index),
//                   pose = centre and orientation (body x = symmetry axis),
//                   scale = 2 (a, b, b): spheres of diameter 2R, spheroids
//                   as scaled, oriented ellipsoids. Grey: carries load;
//                   orange: idle (section 4.5). With more than
//                   max_particles particles only every k-th (storage order,
//                   k = ceil(N / max_particles)) is shown: documented
//                   decimation, the marker ids stay the storage indices.
//   ns "cell"       one LINE_LIST: the 12 edges of the periodic cell.
//   ns "forces"     (strongest_contacts > 0) one LINE_LIST: the strongest
//                   contacts by normal force, centre to centre (partner's
//                   periodic image), coloured blue (weak) to red (strongest).
// The array starts with a DELETEALL marker, so a reloaded specimen leaves no
// stale particles behind. Conversion only: the snapshot comes from
// dem::SpecimenSnapshot (read-only view of the core).
#pragma once

#include <cstddef>
#include <string>

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "virtual_triaxial/dem/specimen_snapshot.h"

namespace vt::ros {

struct MarkerOptions {
  std::string frame = "cell";
  std::size_t max_particles = 20000;     ///< decimation above this
  std::size_t strongest_contacts = 0;    ///< force lines (0: none)
};

visualization_msgs::MarkerArray to_marker_array(const dem::SpecimenSnapshot& s, const MarkerOptions& o,
                                                const ::ros::Time& stamp);

}  // namespace vt::ros
