// triax_bench -- cost per particle-step of the DEM core on a dense sample
// sheared at constant volume (DESIGN §8: flat from 1e3 to 1e5 particles).
//
//   triax_bench --particles N --threads T [--steps S] [--seed K] [--no-sort]
//               [--skin-ratio X] [--cache DIR] [--shape sphere|spheroid] [--aspect K]
//               [--no-sleep] [--handoff auto|plain|streaming]
//   triax_bench --sample FILE [--tile KxKyKz] --threads T [...]
//   triax_bench --sample FILE [--tile KxKyKz] --alternate A,B [--block K] [...]
//   triax_bench --sample FILE [--tile KxKyKz] --threads T --pair-tile KxKyKz
//               [--pair-sample FILE] [--block K] [...]
//
// --sample FILE (issue 13, the default of bench/run_matrix.sh): time a
// prepared sample file (e.g. config/samples/dense_1000.h5, e 0.61, 5.3
// contacts per particle, 100 kPa) instead of the bench's own packing, tiled
// periodically kx x ky x kz times (dem/periodic_tiling.h: same void ratio,
// contacts per particle and stress; --tile 5x5x4 gives 100 000 particles),
// with the sample's own material, damping and c_t. No preparation.
//
// --shape spheroid: prolate spheroids of aspect ratio K (default 1.2) whose
// nominal (equal-volume) radii are the sphere radii below (CloudRequest::
// aspect_ratio); everything else is the same, so the cost per particle-step
// compares directly with the sphere run.
//
// Own packing (without --sample; the loose "extra" of the README):
// Preparation (all hardware threads, progress on stderr), material rho 2650,
// E 70 GPa, nu 0.3, mu 0.5, c_t 0.3, OD damping xi = 0.02:
//   1. radii uniform in [0.8, 1.2] mm; dem::generate_cloud at void ratio 2.0;
//      dem::spatial_sort (slab bin order) unless --no-sort;
//   2. compaction: isotropic compression in blocks of 50 steps, starting at
//      eps' = 1e-3 per axis; after each block the rate is scaled by
//      sqrt(3 MPa / p) (clamped to [0.5, 1.5], at most 1e-3; halved when an
//      overlap exceeds 3 % of a radius) so that the dynamic stress of the
//      collapsing packing stays near 3 MPa; until the mechanical coordination
//      number (idle particles removed) reaches 4.2, i.e. the packing is jammed;
//   3. unloading: a stiffness-normalised servo (Voigt bulk modulus of the
//      contacts, gain 0.5, |eps'| <= 4e-6, p measured every 50 steps) brings
//      the mean stress down to 100 kPa (within 10 % three times in a row);
//   4. 200 steps of relaxation at constant volume.
// Why not xi = 0.2 and a plain stress criterion: the damping acts on the
// velocity relative to the affine field, so a loose cloud compressed at
// eps' ~ 1e-3 carries a drag stress of order 4 xi eps' E (several MPa at
// xi = 0.2) long before it jams, and a hertzian packing at 100 kPa (overlaps
// ~ 6e-4 R) relaxes slowly; compacting at ~3 MPa and unloading slowly gets a
// jammed sample in ~6000 steps whatever N. The sample is dense (e ~ 0.85,
// coordination ~ 3) but not a carefully equilibrated one; for a study sample
// use the protocol's sample preparation.
// Timing (T threads, omp_set_num_threads): constant-volume triaxial
// compression, axial (z) eps' = 1e-5, lateral -1/2 of it; 50 warm-up steps,
// then S steps of Simulation::step(false) timed with steady_clock.
// Default S = max(200, 3e7 / N). --skin-ratio X rebuilds the Simulation from
// its state with SimulationSettings::skin_ratio = X before timing (physics
// unchanged, so the fingerprint must not change; only pairs and rebuilds do).
// --no-sleep: spheroid pairs found apart are tested every step
// (Simulation::set_sleep_apart_pairs(false); same fingerprint, for A/B).
// --handoff MODE: how the integrator stores the particles the other
// thread reads on several threads (dem/handoff_stores.h; default auto;
// same fingerprint, for A/B).
// --alternate A,B [--block K] (instead of --threads): one simulation runs
// on A threads and on B threads in turn, K steps at a time (default 200),
// S steps on each count (so it advances 2S, which rebuilds_during_timing
// and the spheroid counts cover; the results do not depend on the thread
// count, so the fingerprint is that of 2S steps), so a
// drift of the host's speed hits both counts alike (block_turns.h). A
// switch of thread count remakes the threads' runs (thread_runs.h: equal
// runs, re-cut after 20 steps) and the split of the sums (split_sums.h),
// which the blocks' times include (about 1.6 ms per switch to two threads
// at 12 000 spheres). Prints us_per_particle_step_threads_T for both counts
// and alternate_speedup: the median (and quartiles) over pairs of blocks of
// the A block's cost over the B block's, how much faster B threads are.
// --pair-tile KxKyKz [--pair-sample FILE] [--block K] (with --sample): a
// second simulation, of FILE (default the same sample) tiled KxKyKz and
// stored in the same order, set up and warmed up alike, runs in turn with
// the first on the same threads, K steps of each per turn, the order
// alternating (block_turns.h; the same steps, so both are sheared alike: the
// cost falls as the timing shears, e.g. spheroid contacts per particle
// from 3.7 to 2.8 in 600 steps); prints
// us_per_particle_step_pair and pair_cost_ratio: the median (quartiles)
// over pairs of blocks of the second's cost over the first's (the issue's
// x_N1 with the same sample at 12 000 and 10^5; spheroid / sphere with
// the spheroid sample as the pair at the same tile).
// Both print no phase times, and rss_bytes_per_particle then counts both
// simulations (over the first's N); the pair's packing state at the start
// of the timing is printed beside its cost.
//
// Output (stdout), "key: value" lines, us_per_particle_step last:
//   void_ratio_start, contacts_per_particle_start, mean_stress_pa_start: the
//   packing at the start of the timed steps (void_ratio, contacts_per_particle,
//   mean_stress_pa without the suffix: at their end).
//   rss_bytes_per_particle = VmRSS after timing / N. It is the whole process:
//   the Simulation (particles, forces, integrator coefficients, neighbour
//   list with its per-pair data and reverse index), the executable and shared
//   libraries (~5-10 MB, which dominates at N = 1000), the OpenMP runtime and
//   its thread stacks, and heap that glibc still holds after the preparation
//   (malloc_trim(0) is called before timing to give most of it back).
//   cpu_seconds = CPU time of the process over the timed steps (all threads;
//   spinning OpenMP threads count), a cross-check when the machine is shared.
//   peak_rss_mb = VmHWM, the high-water mark over the whole run (preparation,
//   cloud generation and neighbour-list rebuilds included).
//   step_us (median, quantiles and max of the timed steps' wall times [us]),
//   slow_windows (200-step windows whose median step exceeds 1.5x the
//   run's: on this VM, spells where the host ran two threads one after the
//   other) and us_per_particle_step_median_step (the median step / N: the
//   cost outside such spells and the rare rebuild steps); not with
//   --alternate or --pair-tile.
//   state_fingerprint: FNV-1a hash of the final positions, velocities, spins
//   and contact springs; equal fingerprints mean bit-identical states (it does
//   not depend on the thread count; it does on --no-sort, --steps and --seed).
#include <malloc.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/dem/machine_load.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/io/sample_file.h"
#include "block_turns.h"
#include "quantile.h"
#include "wall_clock.h"

using namespace vt::dem;

namespace {

using Clock = vt::bench::WallClock;
using vt::bench::seconds_since;

constexpr double kTargetPressure = 100e3;  // [Pa]
constexpr double kDamping = 0.02;          // OD damping ratio, preparation and shear
constexpr int kBlock = 50;                 // steps between measurements
constexpr double kMaxRate = 1e-3;          // compaction: max eps' per axis
constexpr double kCompactionStress = 3e6;  // compaction: dynamic stress aimed at [Pa]
constexpr double kJammedCoordination = 4.2;
constexpr double kServoGain = 0.5;
constexpr double kServoMaxRate = 4e-6;     // unloading: max |eps'| per axis
constexpr int kRelaxSteps = 200;
constexpr double kShearRate = 1e-5;        // dimensionless axial rate during timing

int usage(const char* msg) {
  if (msg) std::cerr << "triax_bench: " << msg << "\n";
  std::cerr << "usage: triax_bench --particles N --threads T [--steps S] [--seed K] [--no-sort]\n"
               "                   [--skin-ratio X] [--cache DIR] [--shape sphere|spheroid] [--aspect K]\n"
               "  N >= 100 particles, T >= 1 OpenMP threads, S >= 1 timed steps\n"
               "  (default S = max(200, 3e7/N)), K = random seed (default 1),\n"
               "  --no-sort: keep the cloud generator's storage order,\n"
               "  --sort-sample: with --sample, sort the (tiled) sample in space first (spatial_sort.h)\n"
               "  X > 0: Verlet skin / L0 during timing (default: SimulationSettings),\n"
               "  DIR: keep/reuse the prepared sample there (skips the preparation)\n"
               "  --shape spheroid: prolate spheroids of aspect ratio K >= 1 (default 1.2)\n"
               "  --no-sleep: spheroid pairs found apart are tested every step (A/B of sleeping)\n"
               "  --handoff auto|plain|streaming: stores of the particles another thread reads (A/B)\n"
               "  --alternate A,B [--block K]: instead of --threads, A and B threads in turn,\n"
               "  K steps at a time (default 200); prints both costs and the speed-up of B over A\n"
               "  --pair-tile KxKyKz [--pair-sample FILE] [--block K]: with --sample, that sample (default\n"
               "  the same) tiled so, timed in turn with the first; prints its cost and its cost over the first's\n"
               "  --sample FILE [--tile KxKyKz]: time a prepared sample file tiled periodically\n"
               "  (instead of --particles; no preparation)\n";
  return 2;
}

bool parse_int(const char* s, long long lo, long long& out) {
  if (!s || !*s) return false;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s, &end, 10);
  if (errno != 0 || *end != '\0' || v < lo) return false;
  out = v;
  return true;
}

/// Value of a "Vm...:  123 kB" line of /proc/self/status, in bytes (0 if absent).
double proc_status_bytes(const char* key) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::size_t klen = std::strlen(key);
  while (std::getline(f, line))
    if (line.compare(0, klen, key) == 0 && line.size() > klen && line[klen] == ':')
      return std::atof(line.c_str() + klen + 1) * 1024.0;
  return 0.0;
}

/// CPU time of the whole process (all threads) [s].
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Fnv {
  std::uint64_t h = 1469598103934665603ULL;
  void add(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 1099511628211ULL;
  }
};

std::uint64_t fingerprint(const Simulation& sim) {
  Fnv f;
  const Particles& p = sim.particles();
  f.add(p.id.data(), p.id.size() * sizeof(std::int64_t));
  f.add(p.frac.data(), p.frac.size() * sizeof(Vec3));
  f.add(p.velocity.data(), p.velocity.size() * sizeof(Vec3));
  f.add(p.omega.data(), p.omega.size() * sizeof(Vec3));
  if (sim.neighbor_list().has_spheroids())  // spheres: unchanged fingerprint
    f.add(p.orientation.data(), p.orientation.size() * sizeof(Quaternion));
  for (const ContactHistory& c : sim.neighbor_list().histories(p)) {
    f.add(&c.id_a, sizeof c.id_a);
    f.add(&c.id_b, sizeof c.id_b);
    f.add(&c.spring, sizeof c.spring);
  }
  const Mat3& h = sim.cell().h();
  f.add(&h, sizeof h);
  return f.h;
}

/// Voigt estimate of the bulk modulus from the contact stiffnesses:
/// K = sum_c k_n |d_c|^2 / (9 V), k_n = E/(1-nu^2) sqrt(R* delta) (eq. 116) [Pa].
double bulk_stiffness(const Simulation& sim) {
  const Particles& p = sim.particles();
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const Material& mat = sim.settings().material;
  const double kc = mat.young / (1.0 - mat.poisson * mat.poisson);
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (std::int32_t e = off[i]; e < off[i + 1]; ++e) {
      const double hov = pd.half_overlap[static_cast<std::size_t>(e)];
      if (!(hov > 0.0)) continue;
      const double ri = p.radius[i], rj = p.radius[static_cast<std::size_t>(pd.partner[e])];
      const double delta = 2.0 * hov, d = ri + rj - delta;
      sum += kc * std::sqrt(ri * rj / (ri + rj) * delta) * d * d;
    }
  return sum / (9.0 * sim.cell().volume());
}

/// Run `n` steps, the last one measured; returns false on instability.
bool run_measured(Simulation& sim, int n) {
  for (int k = 0; k + 1 < n; ++k)
    if (!sim.step(false)) return false;
  return sim.step(true);
}

[[noreturn]] void die(const Simulation& sim) {
  std::cerr << "triax_bench: simulation became unstable: " << sim.failure() << "\n";
  std::exit(1);
}

// ---- the timed steps one by one ---------------------------------------------------
// On this 2-vCPU VM two barrier-coupled threads now and then run one after
// the other for a while (bench/host_scaling: S about 1 in some windows,
// for any program); such windows show as runs of steps about twice as
// long. The median step is the cost outside them; slow_windows counts them.
constexpr std::size_t kEpisodeWindow = 200;  // steps
constexpr double kEpisodeFactor = 1.5;       // a window's median over the run's

struct StepEpisodes {
  double median = 0.0;  // the run's median step [us]
  int windows = 0;      // whole windows of kEpisodeWindow steps
  int slow = 0;         // those whose median exceeds factor x median
};

StepEpisodes step_episodes(const std::vector<double>& step_us, std::size_t window, double factor) {
  StepEpisodes ep;
  ep.median = vt::bench::quantile(step_us, 0.5);
  for (std::size_t i = 0; i + window <= step_us.size(); i += window) {
    ++ep.windows;
    const std::vector<double> w(step_us.begin() + static_cast<long>(i), step_us.begin() + static_cast<long>(i + window));
    if (vt::bench::quantile(w, 0.5) > factor * ep.median) ++ep.slow;
  }
  return ep;
}

// ---- prepared-sample cache (--cache DIR) -------------------------------------
// Raw dump of a SimulationState (all plain-old-data vectors), so repeated
// timings of one N skip the preparation. The core is deterministic, so a
// cached state equals a freshly prepared one bit for bit as long as the
// preparation and the physics of the core are unchanged; bump kCacheVersion
// when either changes.
constexpr std::uint64_t kCacheVersion = 4;  // 4: SimulationSettings/State carry the time-step basis

template <class T>
void put(std::FILE* f, const T& v) {
  static_assert(std::is_trivially_copyable<T>::value, "POD only");
  std::fwrite(&v, sizeof v, 1, f);
}
template <class T>
void put_vec(std::FILE* f, const std::vector<T>& v) {
  put(f, static_cast<std::uint64_t>(v.size()));
  if (!v.empty()) std::fwrite(v.data(), sizeof(T), v.size(), f);
}
template <class T>
bool get(std::FILE* f, T& v) {
  return std::fread(&v, sizeof v, 1, f) == 1;
}
template <class T>
bool get_vec(std::FILE* f, std::vector<T>& v) {
  std::uint64_t n = 0;
  if (!get(f, n) || n > (1ULL << 32)) return false;
  v.resize(n);
  return n == 0 || std::fread(v.data(), sizeof(T), n, f) == n;
}

bool save_state(const std::string& path, const SimulationState& s, std::int64_t prep_steps,
                double prep_seconds) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return false;
  put(f, kCacheVersion);
  const Particles& p = s.particles;
  put_vec(f, p.id); put_vec(f, p.shape); put_vec(f, p.radius); put_vec(f, p.semi_axes);
  put_vec(f, p.mass); put_vec(f, p.inertia); put_vec(f, p.frac); put_vec(f, p.velocity);
  put_vec(f, p.omega); put_vec(f, p.orientation); put_vec(f, p.material);
  put(f, s.h); put(f, s.h_reference); put(f, s.velocity_gradient);
  put_vec(f, s.contacts);
  put(f, s.time); put(f, s.step); put(f, s.time_step); put(f, s.contact_critical_step); put(f, s.contact_refresh_virial); put(f, s.energy); put(f, s.settings); put(f, prep_steps);
  put(f, prep_seconds);
  const bool ok = std::fclose(f) == 0;
  return ok && std::rename(tmp.c_str(), path.c_str()) == 0;
}

bool load_state(const std::string& path, SimulationState& s, std::int64_t& prep_steps,
                double& prep_seconds) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  std::uint64_t version = 0;
  Particles& p = s.particles;
  const bool ok = get(f, version) && version == kCacheVersion && get_vec(f, p.id) && get_vec(f, p.shape) &&
                  get_vec(f, p.radius) && get_vec(f, p.semi_axes) && get_vec(f, p.mass) &&
                  get_vec(f, p.inertia) && get_vec(f, p.frac) && get_vec(f, p.velocity) &&
                  get_vec(f, p.omega) && get_vec(f, p.orientation) && get_vec(f, p.material) &&
                  get(f, s.h) && get(f, s.h_reference) && get(f, s.velocity_gradient) &&
                  get_vec(f, s.contacts) && get(f, s.time) && get(f, s.step) && get(f, s.time_step) && get(f, s.contact_critical_step) && get(f, s.contact_refresh_virial) && get(f, s.energy) &&
                  get(f, s.settings) && get(f, prep_steps) && get(f, prep_seconds);
  std::fclose(f);
  return ok;
}

/// Measure every kBlock steps: run kBlock steps, the last one measured.
Measures block(Simulation& sim) {
  if (!run_measured(sim, kBlock)) die(sim);
  return sim.measures();
}

void report(const char* phase, std::int64_t steps, const Measures& m, double rate, Clock::time_point t) {
  std::fprintf(stderr, "[prep] %-10s step %6lld  e %.4f  p %10.4g Pa  Z %.3f  Z_mech %.3f  overlap %.4f  eps' %+.3g  (%.1f s)\n",
               phase, static_cast<long long>(steps), m.void_ratio, m.p, m.raw_coordination_number,
               m.coordination_number, m.max_overlap_ratio, rate, seconds_since(t));
}

/// Compaction, unloading and relaxation (see the header). Returns the steps.
std::int64_t prepare(Simulation& sim, Clock::time_point t_start) {
  const double t0 = sim.time_scale().t0, ct = sim.time_scale().ct;
  std::int64_t steps = 0;
  // Compaction.
  double rate = kMaxRate;
  for (int b = 0;; ++b) {
    sim.set_strain_rates(Vec3{-1, -1, -1} * (rate / t0));
    const Measures m = block(sim);
    steps += kBlock;
    if (b % 10 == 0 || m.coordination_number >= kJammedCoordination) report("compaction", steps, m, rate, t_start);
    if (m.coordination_number >= kJammedCoordination) break;
    double f = m.p > 0.0 ? std::sqrt(kCompactionStress / m.p) : 1.5;
    if (m.max_overlap_ratio > 0.03) f = std::min(f, 0.5);
    rate = std::min(kMaxRate, rate * std::min(1.5, std::max(0.5, f)));
    if (steps > 200000) {
      std::cerr << "triax_bench: the compaction did not jam the sample\n";
      std::exit(1);
    }
  }
  // Unloading to the target pressure.
  Measures m = sim.measures();
  for (int b = 0, ok = 0; ok < 3; ++b) {
    const double k = bulk_stiffness(sim);
    const double strain = kServoGain * (kTargetPressure - m.p) / (3.0 * k);  // per axis, one block
    rate = k > 0.0 ? std::min(kServoMaxRate, std::max(-kServoMaxRate, strain / (kBlock * ct))) : kServoMaxRate;
    sim.set_strain_rates(Vec3{-1, -1, -1} * (rate / t0));
    m = block(sim);
    steps += kBlock;
    ok = std::fabs(m.p / kTargetPressure - 1.0) < 0.1 ? ok + 1 : 0;
    if (b % 10 == 0 || ok == 3) report("unloading", steps, m, rate, t_start);
    if (steps > 400000) {
      std::cerr << "triax_bench: the unloading did not reach the target pressure\n";
      std::exit(1);
    }
  }
  // Relaxation at constant volume.
  sim.set_strain_rates(Vec3{});
  for (int k = 0; k < kRelaxSteps; k += kBlock) m = block(sim);
  steps += kRelaxSteps;
  report("relaxed", steps, m, 0.0, t_start);
  return steps;
}

}  // namespace

int main(int argc, char** argv) {
  long long n = -1, threads = -1, steps = -1, seed = 1;
  std::unique_ptr<Simulation> preloaded;
  std::unique_ptr<Simulation> pair_sim;  // --pair-tile
  bool sort = true;
  bool sort_sample = false;  // --sample: slab-sort the (tiled) sample before timing
  double skin_ratio = -1.0;
  std::string cache_dir;
  bool spheroids = false;
  bool sleep = true;
  HandoffStores::Mode handoff = HandoffStores::Mode::Auto;
  double aspect = 1.2;
  long long alternate[2] = {0, 0};  // --alternate A,B: thread counts taken in turn
  long long block = 200;            // --block: steps per turn
  bool block_given = false;
  std::array<int, 3> pair_tile{0, 0, 0};  // --pair-tile: a second simulation timed in turn
  std::string pair_sample;          // --pair-sample: its sample (default --sample)
  std::string sample;
  std::array<int, 3> tile{1, 1, 1};
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    const char* v = a + 1 < argc ? argv[a + 1] : nullptr;
    if (k == "--particles") {
      if (!parse_int(v, 100, n)) return usage("--particles needs an integer >= 100");
      ++a;
    } else if (k == "--threads") {
      if (v && std::string(v) == "auto") threads = 0;  // ThreadGovernor up to every core
      else if (!parse_int(v, 1, threads)) return usage("--threads needs an integer >= 1 or auto");
      ++a;
    } else if (k == "--alternate") {
      const std::string list = v ? v : "";
      const std::size_t comma = list.find(',');
      if (comma == std::string::npos || !parse_int(list.substr(0, comma).c_str(), 1, alternate[0]) ||
          !parse_int(list.substr(comma + 1).c_str(), 1, alternate[1]) || alternate[0] == alternate[1])
        return usage("--alternate needs two different thread counts A,B >= 1");
      ++a;
    } else if (k == "--pair-tile") {
      const std::optional<std::array<int, 3>> f = v ? vt::dem::parse_tile_factors(v) : std::nullopt;
      if (!f) return usage(vt::dem::tile_factors_usage("--pair-tile").c_str());
      pair_tile = *f;
      ++a;
    } else if (k == "--pair-sample") {
      if (!v || !*v) return usage("--pair-sample needs a sample file");
      pair_sample = v;
      ++a;
    } else if (k == "--block") {
      if (!parse_int(v, 1, block)) return usage("--block needs an integer >= 1");
      block_given = true;
      ++a;
    } else if (k == "--steps") {
      if (!parse_int(v, 1, steps)) return usage("--steps needs an integer >= 1");
      ++a;
    } else if (k == "--seed") {
      if (!parse_int(v, 0, seed)) return usage("--seed needs an integer >= 0");
      ++a;
    } else if (k == "--skin-ratio") {
      char* end = nullptr;
      skin_ratio = v ? std::strtod(v, &end) : -1.0;
      if (!v || *end != '\0' || !(skin_ratio > 0.0 && skin_ratio < 10.0))
        return usage("--skin-ratio needs a number in (0, 10)");
      ++a;
    } else if (k == "--cache") {
      if (!v || !*v) return usage("--cache needs a directory");
      cache_dir = v;
      ++a;
    } else if (k == "--shape") {
      const std::string shape = v ? v : "";
      if (shape != "sphere" && shape != "spheroid") return usage("--shape needs sphere or spheroid");
      spheroids = shape == "spheroid";
      ++a;
    } else if (k == "--aspect") {
      char* end = nullptr;
      aspect = v ? std::strtod(v, &end) : -1.0;
      if (!v || *end != '\0' || !(aspect >= 1.0 && aspect < 10.0)) return usage("--aspect needs a number in [1, 10)");
      ++a;
    } else if (k == "--sample") {
      if (!v || !*v) return usage("--sample needs a sample file");
      sample = v;
      ++a;
    } else if (k == "--tile") {
      const std::optional<std::array<int, 3>> f = v ? vt::dem::parse_tile_factors(v) : std::nullopt;
      if (!f) return usage(vt::dem::tile_factors_usage("--tile").c_str());
      tile = *f;
      ++a;
    } else if (k == "--no-sort") {
      sort = false;
    } else if (k == "--sort-sample") {
      sort_sample = true;
    } else if (k == "--no-sleep") {
      sleep = false;
    } else if (k == "--handoff") {
      const std::string mode = v ? v : "";
      if (mode == "auto") handoff = HandoffStores::Mode::Auto;
      else if (mode == "plain") handoff = HandoffStores::Mode::Plain;
      else if (mode == "streaming") handoff = HandoffStores::Mode::Streaming;
      else return usage("--handoff needs auto, plain or streaming");
      ++a;
    } else if (k == "-h" || k == "--help") {
      return usage(nullptr);
    } else {
      return usage(("unknown argument '" + k + "'").c_str());
    }
  }
  if (!sample.empty()) {
    if (n >= 0) return usage("--sample and --particles exclude each other");
    try {
      SimulationState st = tile_periodic(vt::io::read_sample(sample), tile[0], tile[1], tile[2]);
      n = static_cast<long long>(st.particles.size());
      spheroids = st.particles.has_spheroids();
      sort = sort_sample;
      if (sort) spatial_sort(st);
      preloaded = std::make_unique<Simulation>(st);
      if (pair_tile[0] > 0) {
        const std::string& file = pair_sample.empty() ? sample : pair_sample;
        SimulationState ps = tile_periodic(vt::io::read_sample(file), pair_tile[0], pair_tile[1], pair_tile[2]);
        if (sort) spatial_sort(ps);
        pair_sim = std::make_unique<Simulation>(ps);
      }
    } catch (const std::exception& e) {
      std::cerr << "triax_bench: " << e.what() << "\n";
      return 2;
    }
  }
  const bool alternating = alternate[0] > 0;
  const bool paired = pair_tile[0] > 0;
  const bool in_turns = alternating || paired;
  if (alternating && threads >= 0) return usage("--alternate and --threads exclude each other");
  if (paired && (sample.empty() || alternating)) return usage("--pair-tile needs --sample and excludes --alternate");
  if (paired && threads == 0) return usage("--pair-tile needs a thread count, not auto");
  if (!pair_sample.empty() && !paired) return usage("--pair-sample needs --pair-tile");
  if (block_given && !in_turns) return usage("--block needs --alternate or --pair-tile");
  if (paired && skin_ratio > 0.0) return usage("--skin-ratio and --pair-tile exclude each other");
  if (alternating) threads = alternate[0];
  if (n < 0 || threads < 0) return usage("--particles (or --sample) and --threads (or --alternate) are required");
  if (steps < 0) steps = std::max<long long>(200, static_cast<long long>(3e7 / static_cast<double>(n)));
  if (in_turns && steps < block)
    return usage("--steps must be at least --block with --alternate or --pair-tile (a whole pair of turns)");

  // ---- preparation, all hardware threads -------------------------------------
  omp_set_num_threads(omp_get_num_procs());
  const auto t_prep = Clock::now();
  std::unique_ptr<Simulation> sim = std::move(preloaded);
  std::int64_t prep_steps = 0;
  double prep_seconds = 0.0;
  bool cached = false;
  const std::string cache_file =
      cache_dir.empty() || !sample.empty() ? std::string()
                        : cache_dir + "/triax_bench_n" + std::to_string(n) + "_seed" + std::to_string(seed) +
                              (sort ? "_sorted" : "_unsorted") +
                              (spheroids ? "_spheroid" + std::to_string(aspect) : std::string()) + ".state";
  if (!sim && !cache_file.empty()) {
    SimulationState st;
    if (load_state(cache_file, st, prep_steps, prep_seconds)) {
      sim = std::make_unique<Simulation>(st);
      cached = true;
      std::cerr << "[prep] loaded " << cache_file << "\n";
    }
  }
  if (!sim) {
    Material mat;
    mat.density = 2650.0;
    mat.young = 70e9;
    mat.poisson = 0.3;
    mat.friction = 0.5;
    CloudRequest req;
    req.radii = uniform_radii(n, 0.8e-3, 1.2e-3, static_cast<std::uint64_t>(seed));
    req.density = mat.density;
    req.void_ratio = 2.0;
    req.seed = static_cast<std::uint64_t>(seed);
    if (spheroids) req.aspect_ratio = aspect;
    Cloud cloud = generate_cloud(req);
    std::cerr << "[prep] cloud of " << n << (spheroids ? " spheroids" : " spheres") << " in " << seconds_since(t_prep) << " s ("
              << cloud.box_growths << " box growths)\n";
    if (sort) spatial_sort(cloud.particles, cloud.cell);
    SimulationSettings settings;
    settings.material = mat;
    settings.damping = MassDamping(DampingModel::OD, kDamping);
    settings.time_step_ratio = 0.3;
    sim = std::make_unique<Simulation>(std::move(cloud.particles), cloud.cell, settings);
    prep_steps = prepare(*sim, t_prep);
    prep_seconds = seconds_since(t_prep);
    if (!cache_file.empty()) {
      if (save_state(cache_file, sim->state(), prep_steps, prep_seconds))
        std::cerr << "[prep] saved " << cache_file << "\n";
      else
        std::cerr << "[prep] warning: could not write " << cache_file << "\n";
    }
  }
  std::cerr << "[prep] done in " << seconds_since(t_prep) << " s\n";
  malloc_trim(0);

  // ---- timing, T threads -----------------------------------------------------
  omp_set_num_threads(threads > 0 ? static_cast<int>(threads) : omp_get_num_procs());
  if (skin_ratio > 0.0) {
    SimulationState st = sim->state();
    st.settings.skin_ratio = skin_ratio;
    sim = std::make_unique<Simulation>(st);
  }
  // The timed setup, for the simulation and (--pair-tile) its pair.
  const auto set_up = [&](Simulation& s) {
    s.set_sleep_apart_pairs(sleep);
    s.handoff_stores().set_mode(handoff);
    if (threads == 0) s.set_thread_governor(governor_on_this_machine(omp_get_num_procs()));
    const double shear = kShearRate / s.time_scale().t0;
    s.set_strain_rates({0.5 * shear, 0.5 * shear, -shear});  // constant volume
    for (int k = 0; k < 49; ++k)
      if (!s.step(false)) die(s);
    if (!s.step(true)) die(s);  // the packing timed: its state at the start
  };
  Measures pair_m0;
  if (pair_sim) {
    set_up(*pair_sim);
    pair_m0 = pair_sim->measures();
  }
  set_up(*sim);
  const Measures m0 = sim->measures();
  const std::int64_t rebuilds0 = sim->neighbor_list().rebuild_count();
  const std::uint64_t asleep0 = sim->spheroid_contact_stats().asleep;
  const double cpu0 = process_cpu_seconds();
  sim->reset_phase_times();
  const auto t_run = Clock::now();
  // --alternate: one simulation on two thread counts; --pair-tile: two simulations
  vt::bench::Turn turns[2];
  std::vector<double> turn_ratios;
  std::vector<double> step_us;  // each timed step's wall time [us] (one count, one simulation)
  if (in_turns) {
    turns[0] = {sim.get(), static_cast<int>(threads)};
    turns[1] = {paired ? pair_sim.get() : sim.get(), static_cast<int>(paired ? threads : alternate[1])};
    turn_ratios = vt::bench::run_turns(turns, steps, block, [](const Simulation& s) { die(s); });
  } else {
    step_us.reserve(static_cast<std::size_t>(steps));
    Clock::time_point t_step = Clock::now();
    for (long long k = 0; k < steps; ++k) {
      if (!sim->step(false)) die(*sim);
      const Clock::time_point t_end = Clock::now();
      step_us.push_back(1e6 * vt::bench::seconds_between(t_step, t_end));
      t_step = t_end;
    }
  }
  const double wall = seconds_since(t_run);
  const PhaseTimes phases = sim->phase_times();  // of the timed steps only
  const double cpu = process_cpu_seconds() - cpu0;
  const std::int64_t rebuilds = sim->neighbor_list().rebuild_count() - rebuilds0;
  const std::uint64_t asleep = sim->spheroid_contact_stats().asleep - asleep0;
  const double rss = proc_status_bytes("VmRSS");
  const double hwm = proc_status_bytes("VmHWM");
  if (!sim->step(true)) die(*sim);  // not timed: measures for the report
  const Measures m = sim->measures();

  const double np = static_cast<double>(n);
  // the steps the (first) simulation took while timed: 2S with --alternate
  const long long simulated_steps = alternating ? turns[0].steps + turns[1].steps : steps;
  std::printf("particles: %lld\n", n);
  if (alternating)
    std::printf("threads: %lld and %lld in turn, %lld steps at a time\n", alternate[0], alternate[1], block);
  else if (threads > 0)
    std::printf("threads: %lld\n", threads);
  else
    std::printf("threads: auto (%lld steps on 1, %lld on %d)\n", static_cast<long long>(sim->thread_governor()->steps_one()),
                static_cast<long long>(sim->thread_governor()->steps_max()), sim->thread_governor()->max_threads());
  std::printf("steps: %lld\n", steps);
  std::printf("spatial_sort: %s\n", sort ? "yes" : "no");
  if (!sample.empty()) std::printf("sample: %s tiled %dx%dx%d\n", sample.c_str(), tile[0], tile[1], tile[2]);
  std::printf("shape: %s\n", spheroids ? "spheroid" : "sphere");
  if (spheroids) std::printf("aspect_ratio: %g\n", aspect);
  std::printf("preparation_seconds: %.2f%s\n", prep_seconds, cached ? " (when cached)" : "");
  std::printf("preparation_steps: %lld\n", static_cast<long long>(prep_steps));
  std::printf("void_ratio_start: %.4f\n", m0.void_ratio);
  std::printf("contacts_per_particle_start: %.3f\n", static_cast<double>(m0.contacts) / np);
  std::printf("mean_stress_pa_start: %.1f\n", m0.p);
  std::printf("void_ratio: %.4f\n", m.void_ratio);
  std::printf("contacts_per_particle: %.3f\n", static_cast<double>(m.contacts) / np);
  std::printf("neighbour_pairs_per_particle: %.3f\n",
              static_cast<double>(sim->neighbor_list().pairs().size()) / np);
  std::printf("skin_ratio: %g\n", sim->settings().skin_ratio);
  std::printf("sums_in: %s\n", sim->split_used() ? "each thread's pair loop, with the pairs crossing runs as ghosts"
                                                : "the pair loop");
  if (sim->split_used())
    std::printf("cut_particles: %zu\nghost_pairs: %zu\nthread_run_recuts: %lld\n", sim->cut_particles(),
                sim->ghost_pairs(), static_cast<long long>(sim->thread_runs().recuts()));
  if (sim->handoff_stores().steps() > 0)
    std::printf("handoff_streamed_steps: %lld of %lld\nhandoff_cost_ratio: %.2f\n",
                static_cast<long long>(sim->handoff_stores().streamed_steps()),
                static_cast<long long>(sim->handoff_stores().steps()), sim->handoff_stores().last_ratio());
  std::printf("rebuilds_during_timing: %lld\n", static_cast<long long>(rebuilds));
  std::printf("mean_stress_pa: %.1f\n", m.p);
  if (spheroids) {
    const SpheroidContactStats& cs = sim->spheroid_contact_stats();
    std::printf("spheroid_contact_solves: %llu\n", static_cast<unsigned long long>(cs.solves));
    std::printf("spheroid_iterations_per_solve: %.3f\n",
                cs.solves ? static_cast<double>(cs.iterations) / static_cast<double>(cs.solves) : 0.0);
    std::printf("spheroid_contact_fallbacks: %llu\n", static_cast<unsigned long long>(cs.fallbacks));
    std::printf("spheroid_contact_failures: %llu\n", static_cast<unsigned long long>(cs.failures));
    std::printf("spheroid_pairs_asleep_per_particle_step: %.3f\n",
                static_cast<double>(asleep) / (np * static_cast<double>(simulated_steps)));
  }
  std::printf("state_fingerprint: %016llx\n", static_cast<unsigned long long>(fingerprint(*sim)));
  std::printf("wall_seconds: %.3f\n", wall);
  std::printf("cpu_seconds: %.3f\n", cpu);
  if (alternating) {
    for (const auto& turn : turns)
      std::printf("us_per_particle_step_threads_%d: %.4f (%lld steps)\n", turn.threads, turn.cost() * 1e6, turn.steps);
    std::printf("alternate_speedup: %.3f (median of %zu pairs of blocks; quartiles %.3f %.3f)\n",
                vt::bench::quantile(turn_ratios, 0.5), turn_ratios.size(), vt::bench::quantile(turn_ratios, 0.25),
                vt::bench::quantile(turn_ratios, 0.75));
  }
  if (paired) {
    std::vector<double> inverse;
    for (double r : turn_ratios) inverse.push_back(1.0 / r);
    std::printf("pair: %s tiled %dx%dx%d, %zu particles, %s, %lld steps in blocks of %lld\n",
                (pair_sample.empty() ? sample : pair_sample).c_str(), pair_tile[0], pair_tile[1], pair_tile[2],
                pair_sim->particles().size(), pair_sim->particles().has_spheroids() ? "spheroids" : "spheres",
                turns[1].steps, block);
    std::printf("pair_start: void_ratio %.4f contacts_per_particle %.3f mean_stress_pa %.1f\n", pair_m0.void_ratio,
                static_cast<double>(pair_m0.contacts) / static_cast<double>(pair_sim->particles().size()), pair_m0.p);
    std::printf("us_per_particle_step_pair: %.4f\n", turns[1].cost() * 1e6);
    std::printf("pair_cost_ratio: %.3f (median of %zu pairs of blocks; quartiles %.3f %.3f)\n",
                vt::bench::quantile(inverse, 0.5), inverse.size(), vt::bench::quantile(inverse, 0.25),
                vt::bench::quantile(inverse, 0.75));
  }
  // where the time went (phase_times.h): per thread, seconds in each phase
  // of the timed steps and the rest of the two parallel regions (waits)
  if (!in_turns)
    std::printf("region_seconds: forces %.6f integration %.6f\n", phases.region(PhaseTimes::ForceRegion),
                phases.region(PhaseTimes::IntegrationRegion));
  for (int t = 0; t < phases.threads() && !in_turns; ++t) {
    if (phases.busy(t) == 0.0) continue;  // a slot of a larger team earlier
    std::printf("phase_seconds_thread_%d:", t);
    for (int k = 0; k < PhaseTimes::kPhaseCount; ++k)
      std::printf(" %s %.6f", PhaseTimes::name(static_cast<PhaseTimes::Phase>(k)),
                  phases.seconds(t, static_cast<PhaseTimes::Phase>(k)));
    std::printf(" waits %.6f\n", phases.waits(t));
  }
  // the team's mean waits = imbalance + overhead over both regions; steady:
  // the part of the imbalance a better fixed cut would recover
  for (const auto r : {PhaseTimes::ForceRegion, PhaseTimes::IntegrationRegion})
    if (!in_turns)
      std::printf("region_waits_%s: imbalance %.6f steady %.6f overhead %.6f\n",
                r == PhaseTimes::ForceRegion ? "forces" : "integration", phases.imbalance(r),
                phases.steady_imbalance(r), phases.overhead(r));
  std::printf("peak_rss_mb: %.1f\n", hwm / (1024.0 * 1024.0));
  std::printf("rss_bytes_per_particle: %.0f\n", rss / np);
  if (!step_us.empty()) {
    const StepEpisodes ep = step_episodes(step_us, kEpisodeWindow, kEpisodeFactor);
    std::printf("step_us: median %.1f p10 %.1f p90 %.1f p99 %.1f max %.1f\n", ep.median,
                vt::bench::quantile(step_us, 0.1), vt::bench::quantile(step_us, 0.9), vt::bench::quantile(step_us, 0.99),
                vt::bench::quantile(step_us, 1.0));
    std::printf("slow_windows: %d of %d (%lld-step windows with a median step above %.1fx the run's)\n", ep.slow,
                ep.windows, static_cast<long long>(kEpisodeWindow), kEpisodeFactor);
    std::printf("us_per_particle_step_median_step: %.4f\n", ep.median / np);
  }
  // with --alternate or --pair-tile: the first turn's (wall_seconds holds both)
  const double cost = in_turns ? turns[0].cost() : vt::bench::particle_step_cost(wall, sim->particles().size(), steps);
  std::printf("us_per_particle_step: %.4f\n", cost * 1e6);
  return 0;
}
