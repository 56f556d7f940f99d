// Connects a StageRunner to the HDF5 results file and the terminal: every
// sample is appended to the results time series, flushed to disk (atomically,
// summary verdict `interrupted` until finish()) on the first sample of every
// stage and then at least every `flush_seconds`, so a killed run keeps its
// history up to one interval; progress lines go to stderr.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/results_file.h"
#include "virtual_triaxial/io/run_summary_json.h"
#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::io {

class ResultsRecorder : public protocol::RunObserver {
 public:
  /// Until finish(), the summary on disk says verdict `interrupted` (a
  /// killed run's file says so).
  ResultsRecorder(const std::string& path, bool quiet, double flush_seconds = 20.0);
  /// A resumed run: keeps the first `rows` samples of the file on disk (a
  /// later flush of the killed run may have added more); throws
  /// std::runtime_error naming the file when it has fewer.
  void resume(std::size_t rows);
  /// Samples recorded so far.
  std::size_t rows() const { return writer_.size(); }
  const std::string& path() const { return writer_.path(); }
  /// Flush now, the summary saying `interrupted` with `note`.
  void flush_partial(const std::string& note);
  /// Called after every flush of a running test with the samples and the
  /// stage (the rig writes its partial summary.json there).
  void set_after_flush(std::function<void(std::size_t samples, const std::string& stage)> f) {
    after_flush_ = std::move(f);
  }
  void on_stage_start(const protocol::StageSpec& st, const dem::Simulation& sim) override;
  void on_sample(const protocol::StageSpec& st, const dem::Measures& m) override;
  void on_progress(const std::string& line) override;

  /// Write the summary attributes and flush the file.
  void finish(const protocol::RunReport& report, const dem::Simulation& sim);
  void finish(const protocol::RunReport& report, const RunContext& ctx);
  /// Save a sample file (restartable state) with the scene's provenance.
  void save_sample(const std::string& path, const dem::SimulationState& s, const SceneConfig& scene) const;

 private:
  ResultsWriter writer_;
  bool quiet_;
  double flush_seconds_;
  std::chrono::steady_clock::time_point last_flush_;
  std::string stage_;  ///< stage of the last sample
  std::function<void(std::size_t, const std::string&)> after_flush_;
};

}  // namespace vt::io
