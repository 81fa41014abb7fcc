#include "core/maps/dictionary.h"

#include "core/error.h"
#include "core/maps/manhattan.h"
#include "core/maps/submap.h"

namespace partslam {

Dictionary build_dictionary(const std::string& name, const Scans& scans, const DictionaryConfig& config) {
  if (!(config.resolution > 0)) throw InputError("dictionary: resolution must be > 0");
  if (!(config.max_range > 0)) throw InputError("dictionary: max_range must be > 0 [m]");
  Points2 world;
  for (const Scan& scan : scans) {
    const Points2 pts = points_world(scan, config.max_range);
    world.insert(world.end(), pts.begin(), pts.end());
  }
  return build_dictionary(name, world, config);
}

Dictionary build_dictionary(const std::string& name, const Points2& points, const DictionaryConfig& config) {
  if (!(config.resolution > 0)) throw InputError("dictionary: resolution must be > 0");
  for (const Vec2& p : points) {
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError("dictionary '" + name + "': point coordinates must be finite and within " +
                       std::to_string(kMaxCoordinate) + " m");
  }
  const Points2 world = voxel_downsample(points, config.resolution);
  if (static_cast<int>(world.size()) < config.min_points) {
    throw InputError("dictionary '" + name + "': only " + std::to_string(world.size()) + " points (need " +
                     std::to_string(config.min_points) + ")");
  }
  Dictionary d;
  d.name = name;
  const Vec2 c = centroid(world);
  Points2 centred;
  centred.reserve(world.size());
  for (const Vec2& p : world) centred.push_back(p - c);
  d.alignment_angle = config.align ? manhattan_angle(centred) : 0.0;
  const Pose2 T_dict_centred{0, 0, d.alignment_angle};
  // Re-downsample after rotation so the dictionary keeps one point per cell of its own grid.
  d.points = voxel_downsample(transform(T_dict_centred, centred), config.resolution);
  d.T_world_dict = Pose2{c.x(), c.y(), 0} * T_dict_centred.inverse();
  return d;
}

}  // namespace partslam
