// Shared by `partslam describe`, `render`, `eval` and `demo`: the CPD parameters as command-line options.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/parts/cpd.h"

namespace partslam::apps {

/// The CPD parameters as options of `cmd`, each named --PREFIXNAME (prefix "" for describe and render,
/// "cpd-" for eval and demo): candidates, partitions, corners, box-sizes, corner-radius,
/// corner-spacing, mc, tsize, gc, seed, dilation (of the crop-vs-dictionary fit, Eq. 2).
void add_cpd_options(CLI::App& cmd, CpdConfig& cpd, const std::string& prefix);

/// Refuses a negative seed ("-1" would otherwise wrap to 2^64 - 1 in an unsigned option).
const CLI::Validator& non_negative_seed();

/// CLI::Range(lo, hi), shown in --help as TYPE:[lo,hi] (one word, so the README's usage block keeps the
/// default).
CLI::Validator in_range(double lo, double hi);

}  // namespace partslam::apps
