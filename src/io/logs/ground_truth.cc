#include "io/logs/ground_truth.h"

#include "core/error.h"
#include "core/evaluation/relation_check.h"
#include "core/evaluation/trajectory_check.h"
#include "io/logs/relations.h"
#include "io/logs/scan_source.h"

namespace partslam::io {

GroundTruth load_ground_truth(const std::string& path, const Scans& scans) {
  GroundTruth truth;
  const bool relations = path.size() >= 10 && path.compare(path.size() - 10, 10, ".relations") == 0;
  std::string what;
  if (relations) {
    try {
      truth.reference = reference_from_relations(scans, read_relations(path), truth.index);
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
    what = "relations " + path + " (reference trajectory solved from them)";
  } else {
    truth.reference = load_scan_source(path).scans;
    truth.index = associate_scans(scans, truth.reference);
    what = "corrected twin " + path;
  }
  std::size_t known = 0;
  for (const auto& i : truth.index) known += i.has_value();
  if (known == 0) throw InputError(path + ": names no scan of the log: not its ground truth");
  truth.description = what + ": " + std::to_string(known) + " of " + std::to_string(scans.size()) + " scans";
  return truth;
}

}  // namespace partslam::io
