// Scan Context (Kim & Kim, IROS 2018), the global-descriptor baseline, on 2D submaps. Ranking methods
//   sc       the paper's 20 rings x 60 sectors, one point count per bin (8 bits: 9600 bits per map)
//   sc:128   the same information in 128 bits: 8 rings x 16 sectors of occupancy (1 bit per bin)
// A map's points (canonical frame, centred on its centroid) are binned in polar coordinates around the frame
// origin. The paper stores the maximum point height per bin of a 3D scan; a 2D map has no height, so a bin
// holds how many map points (one per 0.1 m cell) fall in it, or whether any does (binary).
//
// Retrieval is the paper's two steps: a rotation-invariant ring key (per ring, the fraction of its sectors
// that hold a point) shortlists the candidates nearest in L2, then the column-shift distance (the mean cosine
// distance of sector columns, minimised over the circular shifts of the columns) ranks the shortlist.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/types.h"

namespace partslam {


struct ScanContextConfig {
  int rings = 20;    ///< Nr, radial bins (the paper's 20)
  int sectors = 60;  ///< Ns, angular bins (the paper's 60: 6 deg; yaw resolution 2 pi / Ns)
  /// L_max [m]: points farther from the origin are dropped. Default: the radius inscribed in the 12.8 m crop,
  /// so every ring is a full circle of the crop whatever the rotation (the circumscribed 9.05 m would make
  /// the outer rings hold only the crop's corners, which move with the crop, not with the place).
  double max_radius = 6.4;
  /// Occupancy (1 bit per bin) instead of the point count (8 bits per bin, saturating at 255).
  bool binary = false;
  /// Candidates kept by ring-key distance before the column-shift distance; 0 keeps all. The authors'
  /// implementation keeps 10 (its kd-tree candidates), i.e. 10 % of our databases of N = 100.
  int shortlist = 10;
};

/// Throws InputError naming the offending field.
void validate(const ScanContextConfig& config);

/// `sc:128`: 8 rings x 16 sectors (22.5 deg) of occupancy = 128 bits, otherwise the defaults.
ScanContextConfig scan_context_128_config();

/// One map's descriptor. The ring key and the column masks are derived from the bins (not stored extra).
struct ScanContext {
  int rings = 0;
  int sectors = 0;
  bool binary = false;
  /// Sector-major: bins[s * rings + r] is ring r (outward) of sector s (counter-clockwise from +x).
  std::vector<float> bins;
  std::vector<float> ring_key;       ///< per ring: occupied sectors / Ns (rotation invariant)
  std::vector<double> column_norms;  ///< per sector: L2 norm of its column
  std::vector<std::uint64_t> masks;  ///< binary: per sector, bit r set when ring r is occupied

  float bin(int ring, int sector) const { return bins[static_cast<std::size_t>(sector * rings + ring)]; }
  /// Storage [bits]: rings * sectors * (1 if binary, else 8).
  double bits() const;
};

ScanContext make_scan_context(const Points2& points, const ScanContextConfig& config);

/// The column-shift distance of two descriptors of one configuration.
struct ScanContextMatch {
  double distance = 1.0;  ///< in [0, 1]; 0 = identical up to the shift
  int shift = 0;          ///< sectors: b's column j is compared with a's column (j + shift) mod Ns
  double yaw = 0.0;       ///< shift * 2 pi / Ns [rad]: a's points are about b's rotated by yaw
};

/// Mean over sector columns of (1 - cosine similarity) between a's column (j + shift) mod Ns and b's column
/// j. As in the authors' implementation, a column pair where either column is empty is skipped (the mean is
/// over the rest); no column pair left gives 1. On binary bins the cosine is |a & b| / sqrt(|a| |b|).
double column_distance(const ScanContext& a, const ScanContext& b, int shift);

/// The paper's distance: the minimum of column_distance over every shift (the smallest shift on ties).
ScanContextMatch match_scan_contexts(const ScanContext& a, const ScanContext& b);

/// L2 distance of the ring keys.
double ring_key_distance(const ScanContext& a, const ScanContext& b);

/// The highest score of a candidate left out by the ring-key shortlist: below every distance score (those are
/// in [-1, 0]).
inline constexpr double kScanContextShortlistOut = -2.0;

}  // namespace partslam
