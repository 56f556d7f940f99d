// Several RunObservers behind one: every callback goes to each observer in
// the order they were added (e.g. triax_run's results file, then the
// specimen snapshots). Holds references; the observers must outlive it.
// A callback added to RunObserver must be forwarded here too.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::protocol {

class RunObservers : public RunObserver {
 public:
  void add(RunObserver& o) { list_.push_back(o); }
  void on_stage_start(const StageSpec& st, const dem::Simulation& sim) override {
    for (RunObserver& o : list_) o.on_stage_start(st, sim);
  }
  void on_sample(const StageSpec& st, const dem::Measures& m) override {
    for (RunObserver& o : list_) o.on_sample(st, m);
  }
  void on_progress(const std::string& line) override {
    for (RunObserver& o : list_) o.on_progress(line);
  }
  void on_stage_end(const StageOutcome& out) override {
    for (RunObserver& o : list_) o.on_stage_end(out);
  }
  void on_checkpoint(const RunCheckpoint& c, const dem::Simulation& sim) override {
    for (RunObserver& o : list_) o.on_checkpoint(c, sim);
  }

 private:
  std::vector<std::reference_wrapper<RunObserver>> list_;
};

}  // namespace vt::protocol
