// Writes the checkpoints of a headless run (protocol/run_checkpoint.h) to
// `<results>.checkpoint.h5` (checkpoint_file.h): first the results file is
// flushed (summary verdict `interrupted`), then the checkpoint is written
// with the number of samples it goes with, both atomically. So a kill at
// any moment leaves a checkpoint and a results file holding at least its
// samples; `triax_run --resume` continues from there (and drops samples a
// later flush added).
#pragma once

#include <string>

#include "virtual_triaxial/io/results_recorder.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::io {

class CheckpointRecorder : public protocol::RunObserver {
 public:
  /// `scene_path` absolute; `scene_text` the file as the run read it.
  CheckpointRecorder(std::string path, ResultsRecorder& results, std::string scene_path, std::string scene_text,
                     bool quiet)
      : path_(std::move(path)), results_(results), scene_path_(std::move(scene_path)),
        scene_text_(std::move(scene_text)), quiet_(quiet) {}
  void on_checkpoint(const protocol::RunCheckpoint& c, const dem::Simulation& sim) override;
  const std::string& path() const { return path_; }
  int count() const { return count_; }

 private:
  std::string path_;
  ResultsRecorder& results_;
  std::string scene_path_, scene_text_;
  bool quiet_;
  int count_ = 0;
};

/// The checkpoint file of a results file: `<results>.checkpoint.h5`.
inline std::string checkpoint_path(const std::string& results) { return results + ".checkpoint.h5"; }

}  // namespace vt::io
