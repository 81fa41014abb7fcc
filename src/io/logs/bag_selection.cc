#include "io/logs/bag_selection.h"

#include <algorithm>
#include <utility>

namespace partslam::io::rosbag_messages {

BagSelection::BagSelection(std::size_t max_ranges, std::string scan_topic, std::string odom_topic)
    : max_ranges_(max_ranges),
      scan_topic_(std::move(scan_topic)),
      odom_topic_(std::move(odom_topic)),
      scan_asked_(!scan_topic_.empty()),
      odom_asked_(!odom_topic_.empty()) {}

bool BagSelection::wants_scan(const std::string& topic) {
  if (scan_topic_.empty()) scan_topic_ = topic;
  return topic == scan_topic_;
}

void BagSelection::add_scan(const std::string& topic, LaserScanMessage message) {
  if (!wants_scan(topic)) return;
  ranges_ += message.ranges.size();
  if (ranges_ > max_ranges_)
    throw BagError("more than " + std::to_string(max_ranges_) + " ranges (LogReadOptions.max_points)");
  out_.scan_topic = topic;
  out_.scans.push_back(std::move(message));
}

bool BagSelection::wants_odometry(const std::string& topic) {
  if (odom_topic_.empty()) odom_topic_ = topic;
  return topic == odom_topic_;
}

void BagSelection::add_odometry(const std::string& topic, const std::string& child_frame,
                                const OdometryMessage& message) {
  if (!wants_odometry(topic)) return;
  out_.odometry_topic = topic;
  if (out_.base_frame.empty()) out_.base_frame = child_frame;
  out_.odometry.push_back(message);
}

void BagSelection::add_transform(const std::string& topic, double stamp, const FrameTransform& f) {
  if (f.parent != "odom" || (f.child != "base_link" && f.child != "base_footprint")) {
    const auto same = [&](const FrameTransform& g) { return g.parent == f.parent && g.child == f.child; };
    if (std::none_of(out_.transforms.begin(), out_.transforms.end(), same)) out_.transforms.push_back(f);
    return;
  }
  // odom -> base: the robot's odometry, used when no Odometry topic poses the scans (or this topic was asked for).
  if (!odom_topic_.empty() && topic != odom_topic_) return;
  if (!tf_topic_.empty() && topic != tf_topic_) return;
  if (tf_child_.empty()) tf_topic_ = topic, tf_child_ = f.child;
  if (f.child != tf_child_) return;
  tf_odometry_.push_back({stamp, f.x, f.y, f.qx, f.qy, f.qz, f.qw});
}

void BagSelection::note_topic(const std::string& topic, const std::string& type) {
  const std::string entry = topic + " (" + type + ")";
  if (std::find(topics_.begin(), topics_.end(), entry) == topics_.end()) topics_.push_back(entry);
}

BagMessages BagSelection::finish() && {
  if (out_.odometry_topic.empty() && !tf_odometry_.empty()) {
    out_.odometry_topic = tf_topic_ + " (odom -> " + tf_child_ + ")";
    out_.base_frame = tf_child_;
    out_.odometry = std::move(tf_odometry_);
  }
  std::string topics;
  for (const std::string& t : topics_) topics += (topics.empty() ? "" : ", ") + t;
  if (scan_asked_ && out_.scans.empty())
    throw BagError("no LaserScan message on " + scan_topic_ + " (the bag's topics: " + topics + ")");
  if (odom_asked_ && out_.odometry.empty())
    throw BagError("no Odometry message or odom -> base_link transform on " + odom_topic_ +
                   " (the bag's topics: " + topics + ")");
  return std::move(out_);
}

}  // namespace partslam::io::rosbag_messages
