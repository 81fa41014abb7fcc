// A scanner that saw nothing along a beam writes a code instead of a range. CARMEN's own codes (81.83 .. 81.92) lie
// above LogReadOptions::no_return_range and are dropped as each beam is read; a scanner's maximum is another code,
// and it differs from log to log (50.0 m in aces, about 51.1 m in acapulco, edmonton, fhw and the infinite
// corridor, 32.77 m in orebro), so it is found in the whole recording once it is read: real returns beyond
// `no_return_code_min_range` spread over many centimetres of range, a code piles up in one. A 1 cm bin holding at
// least `no_return_code_share` of the recording's beams, and kNoReturnCodePeak times the mean bin within 0.5 m of
// it (outside its own window), is a code (the shared logs' codes hold 0.55 to 5.9 % of their beams in one bin,
// their real far returns at most 0.06 %; docs/NOTES.md, "Far returns kept"). The second test keeps a far wall
// that a parked robot faced for long from being taken for one. Every beam within kNoReturnCodeWindow of a code is
// dropped, and so is every beam beyond the farthest code when no more than stragglers lie there (at most 1 % of
// that code's beams: the maximum jitters by a few centimetres).
#pragma once

#include <cstddef>
#include <vector>

#include "core/maps/scan.h"
#include "io/logs/log_read_options.h"

namespace partslam::io {

/// Beams this close to a code (either side) are the code [m].
inline constexpr double kNoReturnCodeWindow = 0.1;
/// A code's bin holds at least this many times the mean bin around it.
inline constexpr double kNoReturnCodePeak = 20.0;
/// Codes are looked for up to this far beyond LogReadOptions::no_return_code_min_range [m].
inline constexpr double kNoReturnCodeSpan = 200.0;

/// The codes of a recording's scans (ranges [m], ascending, each the centre of its 1 cm bin); none when
/// options.no_return_code_share is 0.
std::vector<double> find_no_return_codes(const Scans& scans, const LogReadOptions& options);

/// Drops the beams of `codes` (within kNoReturnCodeWindow of one, and beyond the farthest unless more than
/// stragglers lie there) from every scan's points; returns how many were dropped.
std::size_t drop_no_return_codes(Scans& scans, const std::vector<double>& codes);

}  // namespace partslam::io
