// Test helper: several "processes" played by threads that exchange their records like MPI ranks (an in-memory
// all-gather of their bytes), to test code written against core/work_split.h without MPI.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <span>
#include <vector>

#include "core/work_split.h"

namespace partslam::testing {

class ThreadExchange {
 public:
  explicit ThreadExchange(int size) : slots_(static_cast<std::size_t>(size)) {}
  std::vector<std::byte> all_gather(int rank, std::span<const std::byte> mine) {
    std::unique_lock lock(mutex_);
    const std::size_t round = round_;
    slots_[static_cast<std::size_t>(rank)].assign(mine.begin(), mine.end());
    if (++arrived_ == slots_.size()) {
      gathered_.clear();
      for (const std::vector<std::byte>& s : slots_) gathered_.insert(gathered_.end(), s.begin(), s.end());
      arrived_ = 0, ++round_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return round_ != round; });
    }
    return gathered_;  // read under the lock; the next round cannot start before every thread has left this one
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::vector<std::byte>> slots_;
  std::vector<std::byte> gathered_;
  std::size_t arrived_ = 0, round_ = 0;
};

class ThreadSplit : public WorkSplit {
 public:
  /// `records` counts the records this process sends.
  ThreadSplit(int rank, ThreadExchange* exchange, std::size_t* records) : rank_(rank), exchange_(exchange), records_(records) {}
  int rank() const override { return rank_; }
  int size() const override { return 2; }
  std::vector<std::byte> all_gather_bytes(std::span<const std::byte> mine, std::size_t record_size) const override {
    *records_ += mine.size() / record_size;
    return exchange_->all_gather(rank_, mine);
  }

 private:
  int rank_;
  ThreadExchange* exchange_;
  std::size_t* records_;
};

}  // namespace partslam::testing
