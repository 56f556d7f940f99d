// triax_run SCENE.yaml [--out results.h5] [--save-sample final.h5] [--specimen DIR] [--quiet] [--check]
//                  [--threads N|auto] [--governor-log FILE.csv]
// triax_run --resume OUTDIR_OR_RESULTS [--save-sample ...] [--specimen ...] [--quiet] [--threads ...]
//
// Checkpoints: during the run, `<out>.checkpoint.h5` (io/checkpoint_file.h)
// is rewritten atomically on the first sample after output.checkpoint_ticks
// control ticks or output.checkpoint_seconds (default 60) wall seconds, the
// results file flushed just before it; it is removed when the run ends.
// --resume continues a killed run from it (the scene it names must be
// unchanged) into the same results file: the finished run equals the
// uninterrupted one bit for bit (samples, summary; not the wall time).
//
// --check only reads and validates the file, the run limits included
// (io/run_limits.h; without the specimen, so rates given in 1/s, which need
// its T0, are checked when the run starts): exit 0 valid, 2 bad input with
// the one-line error naming the field; triax_sweep checks its inputs so.
//
// --threads auto (default): up to OMP_NUM_THREADS (else every core), chosen
// at run time by measurement (dem/thread_governor.h), so that a busy machine
// makes the run fall back to one thread instead of waiting at barriers;
// --threads N: exactly N OpenMP threads. Results are bit-identical either way.
// --governor-log FILE.csv (with --threads auto): the governor's blocks, one
// row each (io/governor_log.h: the count each ran, its cost per step, the
// count chosen next), written when the run ends.
//
// --specimen DIR: VTK snapshots of the specimen in DIR at every stage start
// and end and every output.snapshot_interval steps (io/snapshot_recorder.h),
// then the section pictures DIR/section_*.png (scripts/specimen_section.py;
// a failure to render is a warning, not an error).
// Runs a scene headless: prints progress on stderr, writes an HDF5 time
// series of all measures, prints a JSON summary as its last stdout line.
// Exit codes: 0 completed, 2 bad input, 3 numerical failure (unstable),
// 4 a stage hit the step limit before its stop criterion, 5 aborted,
// 6 an output file could not be written (full disk, permissions: one line
// naming the file; the files written before, e.g. the last flush of the
// results, are intact and valid).
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/machine_load.h"
#include "virtual_triaxial/io/checkpoint_file.h"
#include "virtual_triaxial/io/checkpoint_recorder.h"
#include "virtual_triaxial/io/governor_log.h"
#include "virtual_triaxial/io/hdf5_atomic_file.h"
#include "virtual_triaxial/io/run_limits.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/io/results_recorder.h"
#include "virtual_triaxial/io/run_summary_json.h"
#include "virtual_triaxial/io/snapshot_recorder.h"
#include "virtual_triaxial/io/text_file.h"
#include "virtual_triaxial/io/vtk_snapshot_writer.h"
#include "virtual_triaxial/protocol/run_observers.h"

extern char** environ;
namespace fs = std::filesystem;

namespace {

struct Args {
  std::string scene, out = "results.h5", save_sample, specimen, resume, governor_log;
  bool quiet = false;
  bool check = false;
  int threads = 0;  ///< 0 = auto
};

int usage(const char* msg) {
  std::fprintf(stderr, "triax_run: %s\nusage: triax_run SCENE.yaml [--out results.h5] [--save-sample final.h5] "
                       "[--specimen DIR] [--quiet] [--check] [--threads N|auto] [--governor-log FILE.csv]\n"
                       "       triax_run --resume OUTDIR_OR_RESULTS [--save-sample final.h5] [--specimen DIR] [--quiet] "
                       "[--threads N|auto] [--governor-log FILE.csv]\n", msg);
  return 2;
}

/// scripts/specimen_section.py DIR: the section pictures of the snapshots.
void render_sections(const std::string& dir, bool quiet) {
  const std::string script = std::string(VT_SCRIPTS_DIR) + "/specimen_section.py";
  std::vector<std::string> args = {"/usr/bin/python3", script, dir};
  if (quiet) args.push_back("--quiet");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  int status = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0 || waitpid(pid, &status, 0) < 0 ||
      !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    std::fprintf(stderr, "triax_run: warning: no section pictures (%s %s failed); the snapshots are in %s\n",
                 script.c_str(), dir.c_str(), dir.c_str());
}

/// The whole file ("" when it cannot be read).
std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Test hook: VT_TEST_KILL_AT_SAMPLE=S kills the process (SIGKILL, as
/// kill -9 would) when its S-th sample is recorded, so the fault tests kill
/// a run at a known point.
class KillHook : public vt::protocol::RunObserver {
 public:
  KillHook() {
    if (const char* v = std::getenv("VT_TEST_KILL_AT_SAMPLE")) at_ = std::atol(v);
  }
  void on_sample(const vt::protocol::StageSpec&, const vt::dem::Measures&) override {
    if (at_ > 0 && ++seen_ == at_) ::raise(SIGKILL);
  }

 private:
  long at_ = 0, seen_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if ((s == "--out" || s == "--save-sample") && i + 1 < argc) (s == "--out" ? a.out : a.save_sample) = argv[++i];
    else if (s == "--specimen" && i + 1 < argc) a.specimen = argv[++i];
    else if (s == "--resume" && i + 1 < argc) a.resume = argv[++i];
    else if (s == "--governor-log" && i + 1 < argc) a.governor_log = argv[++i];
    else if (s == "--quiet") a.quiet = true;
    else if (s == "--check") a.check = true;
    else if (s == "--threads" && i + 1 < argc) {
      const std::string v = argv[++i];
      char* end = nullptr;
      const long t = v == "auto" ? 0 : std::strtol(v.c_str(), &end, 10);
      if (v != "auto" && (v.empty() || *end != '\0' || t < 1 || t > 1024))
        return usage("--threads: must be auto or a whole number >= 1");
      a.threads = static_cast<int>(t);
    }
    else if (s == "-h" || s == "--help") return usage("help"), 0;
    else if (!s.empty() && s[0] == '-') return usage(("unknown option " + s).c_str());
    else if (a.scene.empty()) a.scene = s;
    else return usage(("unexpected argument " + s).c_str());
  }
  if (!a.governor_log.empty() && a.threads > 0)
    return usage("--governor-log: the governor runs with --threads auto only (the count is fixed with --threads N)");
  // --resume: the results file (in OUTDIR: results.h5), its checkpoint and the scene it names.
  std::optional<vt::io::CheckpointFile> resume;
  if (!a.resume.empty()) {
    if (!a.scene.empty()) return usage("--resume takes no SCENE.yaml: the checkpoint names it");
    if (a.check) return usage("--check and --resume exclude each other");
    a.out = fs::is_directory(a.resume) ? (fs::path(a.resume) / "results.h5").string() : a.resume;
    const std::string cp = vt::io::checkpoint_path(a.out);
    if (!fs::exists(cp)) {
      std::fprintf(stderr, "triax_run: error: --resume: no checkpoint %s (the run finished, or stopped before its "
                           "first checkpoint: run it again)\n", cp.c_str());
      return 2;
    }
    try {
      resume = vt::io::read_checkpoint(cp);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "triax_run: error: --resume: %s\n", e.what());
      return 2;
    }
    a.scene = resume->scene_path;
    if (read_text(a.scene) != resume->scene_text) {
      std::fprintf(stderr, "triax_run: error: --resume: %s: changed since the checkpoint (the resumed test would "
                           "not be the one that was started)\n", a.scene.c_str());
      return 2;
    }
  }
  if (a.scene.empty()) return usage("missing SCENE.yaml");

  vt::io::SceneConfig scene;
  try {
    scene = vt::io::load_scene(a.scene);
  } catch (const vt::io::SceneError& e) {
    std::fprintf(stderr, "triax_run: error: %s\n", e.what());
    return 2;
  }
  // The limits both runners share (io/run_limits.h), before anything is built.
  if (const std::string bad = vt::io::check_scene_limits(scene); !bad.empty()) {
    std::fprintf(stderr, "triax_run: error: %s\n", bad.c_str());
    return 2;
  }
  if (a.check) {  // no specimen is built (a sample file is read only when the run starts): T0 unknown
    if (const std::string bad = vt::io::check_rate_limits(scene, 0.0); !bad.empty()) {
      std::fprintf(stderr, "triax_run: error: %s\n", bad.c_str());
      return 2;
    }
    std::printf("triax_run: %s: valid\n", a.scene.c_str());
    return 0;
  }
  if (scene.time_step_warning)
    std::fprintf(stderr, "triax_run: warning: time_step_ratio = %g >= 1: the time step exceeds the critical "
                         "estimate T0 (eq. 91-92); expect an unstable run\n", scene.time_step_ratio);
  try {
    vt::dem::Simulation sim = resume ? vt::dem::Simulation(resume->state) : vt::io::build_simulation(scene);
    // The rate limits need T0, known once the specimen is built.
    if (const std::string bad = vt::io::check_rate_limits(scene, sim.time_scale().t0); !bad.empty()) {
      std::fprintf(stderr, "triax_run: error: %s\n", bad.c_str());
      return 2;
    }
    vt::io::GovernorLog governor_log;
    if (a.threads > 0) omp_set_num_threads(a.threads);
    else {
      vt::dem::ThreadGovernor g = vt::dem::governor_on_this_machine(omp_get_max_threads());
      if (!a.governor_log.empty()) g.set_block_log([&governor_log](const auto& b) { governor_log.add(b); });
      sim.set_thread_governor(std::move(g));
    }
    if (const auto& g = sim.thread_governor(); g && g->max_threads() < omp_get_max_threads())
      std::fprintf(stderr, "triax_run: %zu particles: at most %d thread(s) of %d (fewer than %d chunks of %d per thread)\n",
                   sim.particles().size(), g->max_threads(), omp_get_max_threads(),
                   vt::dem::ThreadGovernor::kMinChunksPerThread, vt::dem::kChunkSize);
    // The last good state of a run that fails before its first sample.
    const vt::dem::SimulationState initial = sim.state();
    vt::io::ResultsRecorder recorder(a.out, a.quiet);
    if (resume) recorder.resume(static_cast<std::size_t>(resume->results_rows));
    std::fprintf(stderr, "triax_run: %zu particles, L0 = %.4g m, T0 = %.4g s, %s, damping %s xi = %g\n",
                 sim.particles().size(), sim.time_scale().l0, sim.time_scale().t0,
                 vt::dem::describe_time_step(sim).c_str(),
                 vt::dem::to_string(scene.damping.model()), scene.damping.ratio());
    vt::protocol::RunOptions opt = scene.run_options();
    if (a.quiet) opt.progress_seconds = 0.0;
    vt::protocol::StageRunner runner(sim, opt);
    vt::protocol::RunObservers observers;
    observers.add(recorder);
    vt::io::CheckpointRecorder checkpoints(vt::io::checkpoint_path(a.out), recorder,
                                           fs::absolute(a.scene).lexically_normal().string(), read_text(a.scene),
                                           a.quiet);
    observers.add(checkpoints);
    KillHook kill_hook;  // the fault-injection tests' kill -9 (VT_TEST_KILL_AT_SAMPLE)
    observers.add(kill_hook);
    std::unique_ptr<vt::io::VtkSnapshotSeries> series;
    std::unique_ptr<vt::io::SnapshotRecorder> snapshots;
    if (!a.specimen.empty()) {
      series = std::make_unique<vt::io::VtkSnapshotSeries>(a.specimen);
      snapshots = std::make_unique<vt::io::SnapshotRecorder>(sim, *series, scene.output.snapshot_interval);
      observers.add(*snapshots);
    }
    const vt::protocol::RunReport report = runner.run(scene.stages, observers, resume ? &resume->run : nullptr);
    recorder.finish(report, sim);
    std::error_code ec;  // finished: nothing to resume (a full disk keeps the checkpoint: exit 6 below)
    fs::remove(checkpoints.path(), ec);
    const auto& governor = sim.thread_governor();
    const bool governed = governor && governor->max_threads() > 1;  // the count chosen at run time
    if (governed)
      std::fprintf(stderr, "triax_run: threads chosen at run time: %lld steps on 1, %lld on %d\n",
                   static_cast<long long>(governor->steps_one()), static_cast<long long>(governor->steps_max()),
                   governor->max_threads());
    if (report.verdict == vt::protocol::Verdict::Unstable) {
      const std::string path = a.out + ".last_good.h5";
      recorder.save_sample(path, report.last_good ? *report.last_good : initial, scene);
      std::fprintf(stderr, "triax_run: unstable: %s\ntriax_run: last good state saved to %s\n",
                   report.failure.c_str(), path.c_str());
    }
    if (!a.save_sample.empty()) recorder.save_sample(a.save_sample, sim.state(), scene);
    if (series) {
      std::fprintf(stderr, "triax_run: %zu specimen snapshots in %s\n", series->count(), a.specimen.c_str());
      render_sections(a.specimen, a.quiet);
    }
    if (!a.governor_log.empty()) {  // a diagnostic, written last: a failure to write it only warns
      try {
        vt::io::write_text_atomic(a.governor_log, governor_log.text());
        if (!a.quiet)
          std::fprintf(stderr, "triax_run: %zu governor blocks in %s%s\n", governor_log.blocks(),
                       a.governor_log.c_str(),
                       governed ? "" : " (at most one thread here: OMP_NUM_THREADS or too few chunks, so no blocks)");
      } catch (const vt::io::WriteError& e) {
        std::fprintf(stderr, "triax_run: warning: --governor-log not written: %s\n", e.what());
      }
    }
    std::printf("%s\n", vt::io::run_summary_json(report, sim, a.out).c_str());
    switch (report.verdict) {
      case vt::protocol::Verdict::Completed: return 0;
      case vt::protocol::Verdict::Unstable: return 3;
      case vt::protocol::Verdict::StepLimit: return 4;
      case vt::protocol::Verdict::Aborted:
      case vt::protocol::Verdict::Preempted: return 5;
    }
  } catch (const vt::io::WriteError& e) {
    std::fprintf(stderr, "triax_run: output: %s\n", e.what());
    return 6;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "triax_run: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "triax_run: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
