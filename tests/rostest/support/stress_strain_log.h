// The rig's /stress and /strain as a test node receives them, kept by
// control tick (header-only; used by the protocol-rig and drained-mini test
// clients). Callbacks run on the node's spinner thread, readers on the
// test's: one mutex guards both maps.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include <ros/ros.h>

#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

namespace vt::rostest {

class StressStrainLog {
 public:
  explicit StressStrainLog(::ros::NodeHandle& nh) {
    stress_sub_ = nh.subscribe("stress", 100000, &StressStrainLog::on_stress, this);
    strain_sub_ = nh.subscribe("strain", 100000, &StressStrainLog::on_strain, this);
  }
  StressStrainLog(const StressStrainLog&) = delete;
  StressStrainLog& operator=(const StressStrainLog&) = delete;

  /// Both topics have a publisher.
  bool connected() const { return stress_sub_.getNumPublishers() > 0 && strain_sub_.getNumPublishers() > 0; }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    stress_.clear();
    strain_.clear();
  }
  /// Both messages of tick k have arrived.
  bool has(std::uint64_t k) {
    std::lock_guard<std::mutex> lock(mutex_);
    return stress_.count(k) && strain_.count(k);
  }
  /// Appends the messages of ticks first..last in order, up to the first
  /// tick that misses one of them; returns that tick (last + 1: none missing).
  std::uint64_t copy(std::uint64_t first, std::uint64_t last, std::vector<virtual_triaxial::Stress>& stress,
                     std::vector<virtual_triaxial::Strain>& strain) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::uint64_t k = first; k <= last; ++k) {
      const auto a = stress_.find(k);
      const auto b = strain_.find(k);
      if (a == stress_.end() || b == strain_.end()) return k;
      stress.push_back(a->second);
      strain.push_back(b->second);
    }
    return last + 1;
  }

 private:
  void on_stress(const virtual_triaxial::Stress::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    stress_[m->tick] = *m;
  }
  void on_strain(const virtual_triaxial::Strain::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    strain_[m->tick] = *m;
  }

  ::ros::Subscriber stress_sub_, strain_sub_;
  std::mutex mutex_;
  std::map<std::uint64_t, virtual_triaxial::Stress> stress_;
  std::map<std::uint64_t, virtual_triaxial::Strain> strain_;
};

}  // namespace vt::rostest
