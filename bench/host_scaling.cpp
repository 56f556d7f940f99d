// host_scaling -- how much two threads can gain over one on this machine,
// whatever the program: the ceiling beside which issue 13's "two threads
// >= 1.8x one" is read (bench/two_thread_ceiling.sh runs it beside ours).
//
//   host_scaling [--rounds R] [--seconds S]
//   host_scaling --pingpong [--rounds R]     (the round trip alone, 13-50
//                                             ms a round: beside another run)
//
// Each round times seven kernels, each as one thread alone on CPU 0, alone
// on CPU 1, then as two threads together (one pinned to each CPU, started
// at one barrier), every thread doing the same fixed work:
//   compute  16 independent multiply-add chains in registers (no memory):
//            latency-bound, so two threads on one core's SMT siblings
//            still run nearly as fast as alone;
//   fma      128 chains: throughput-bound, the core's multiply-add units
//            full, as in the DEM's 16-lane contact law, so two threads
//            sharing one core run about half as fast each (S near 1).
//            Built with -march=native on this AVX-512 host the chains are
//            16 zmm registers (objdump: 16 vfmadd132pd per iteration); on
//            an AVX2 host they would spill to memory;
//   sync     the same work in slices of 300 us with a spinning barrier
//            (PAUSE in its loop, as libgomp's) after each: two per step,
//            as the DEM step at 12 000 spheres on two threads. Together,
//            each slice waits for the slower thread, so a vCPU held up for
//            a moment holds up both;
//   syncnp   the same with a barrier that spins without PAUSE (so without
//            the hypervisor's pause-loop exits);
//   syncblk  the same with a barrier that waits asleep (pthread barrier: a
//            futex, the vCPU halts), as OpenMP threads do after their spin;
//   cache    v = 0.5 v + 1 over a private 6 MiB buffer per thread (both
//            together 12 MiB: in the shared 32 MiB L3, not in a 1 MiB L2,
//            like the 12 000-sphere step's data);
//   memory   the same over 96 MiB per thread (main memory).
// and, after them, pingpong: the round trip of one cache line between a
// thread on CPU 0 and one on CPU 1 [ns] (round_trip_ns below), the latency
// every line shared by two DEM threads pays when it changes hands.
// For a kernel, with t_solo0, t_solo1 the solo times and t_0, t_1 the
// two threads' times together, the host's speed-up of a job split evenly
// over two threads is
//   S = (t_solo0 + t_solo1) / max(t_0, t_1)                (dimensionless)
// (2 when the two CPUs run together as fast as alone; 1 when they share
// one core or the hypervisor runs only one of them at a time). Each line
// also prints the slow-downs t_0 / t_solo0 and t_1 / t_solo1 and the share
// of the kernel's time the hypervisor took from this VM (steal, /proc/stat:
// vt::dem::steal_share; -1 when unreadable).
//
// Output: one line per round and kernel and the round's pingpong line, then
// the medians of S per kernel and of the round trip.
// The work per kernel is sized once, so a solo compute, fma, cache or memory
// run takes about S seconds (default 0.15; the sync kernels about twice that, in
// slices of 300 us).
// Both CPUs must be available to this process (taskset).
//
// Measured on this 2-vCPU VM (session 23, rounds of 0.1 s;
// bench/results/2026-12-03-s23/host_scaling_*.txt): compute S 1.82-2.05 in
// 102 rounds; sync and syncnp median 1.96-1.98 and syncblk 1.81 (slices
// of 300 us; 600 us in the 50 rounds without syncblk), but in a
// few windows the two threads ran one after the other, S 0.98-1.05 (each
// thread about twice as slow together as alone): sync and syncnp 1 each
// of 102, syncblk 4 of 52 (and S below 1.6 in 3, 3 and 5); cache 1.03-2.59;
// memory 0.94-2.14. So barrier-coupled work on two vCPUs here loses whole
// windows to the host's placement of the two vCPUs, whatever the program
// and the barrier; uncoupled work did not. Session 34 (fma added): S_fma
// 1.85-2.03 in 50 rounds, also while two DEM threads at 12 000 spheres
// dropped to 1.4x one (bench/results/2026-12-04-s34/experiments.txt): the
// vCPUs did not share a core then. Session 35 (pingpong added): the round
// trip reads about 95-145 ns in most windows and 465-535 ns in others
// (the host's placement of the two vCPUs); the DEM's two-thread drops come
// with the second kind (bench/results/2026-12-04-s35/experiments.txt).
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "virtual_triaxial/dem/machine_load.h"
#include "quantile.h"
#include "wall_clock.h"

namespace {

using Clock = vt::bench::WallClock;
using vt::bench::seconds_since;

/// The sync kernel's slice between barriers [s]: two barriers in a
/// 600 us step, as two threads take 12 000 spheres.
constexpr double kSliceSeconds = 300e-6;
/// pingpong: bursts of round trips per round (13-50 ms in all here).
constexpr long kRoundTrips = 20000;
constexpr int kRoundTripBursts = 5;

/// Volatile sink so the kernels' results are used.
struct Sink {
  volatile double value = 0.0;
};

/// compute (Chains = 16) and fma (Chains = 128): Chains chains
/// x = x m + c, `reps` times; returns their sum. 16 chains are two SIMD
/// registers of multiply-adds waiting on their own latency, so one core
/// has room for a second such thread; 128 keep the core's multiply-add
/// units busy, so two threads sharing one core (SMT siblings on the host)
/// run half as fast each.
template <int Chains>
double compute_kernel(long reps) {
  double x[Chains];
  for (int k = 0; k < Chains; ++k) x[k] = 1.0 + 1e-4 * k;  // all distinct: no two chains merge
  const double m = 0.999999, c = 1e-7;
  for (long r = 0; r < reps; ++r) {
    for (int k = 0; k < Chains; ++k) x[k] = x[k] * m + c;
  }
  double s = 0.0;
  for (double v : x) s += v;
  return s;
}

/// cache / memory: v = 0.5 v + 1 over buf[0, n) `reps` times; returns a sum.
double stream_kernel(double* buf, std::size_t n, long reps) {
  double s = 0.0;
  for (long r = 0; r < reps; ++r) {
    for (std::size_t i = 0; i < n; ++i) buf[i] = 0.5 * buf[i] + 1.0;
    s += buf[static_cast<std::size_t>(r) % n];
  }
  return s;
}

bool pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0;
}

/// How the sliced kernels' threads wait for each other.
enum class Wait {
  None,         // no barrier: compute, cache, memory
  Spin,         // spinning with PAUSE in the loop, as libgomp's threads do at first
  SpinNoPause,  // spinning without PAUSE (no pause-loop exits to the hypervisor)
  Asleep,       // a pthread barrier (a futex: the vCPU halts), as OpenMP threads after their spin
};

/// The barrier of two threads running a sliced kernel together.
class SliceBarrier {
 public:
  explicit SliceBarrier(Wait wait) : wait_(wait) { pthread_barrier_init(&sleeping_, nullptr, 2); }
  ~SliceBarrier() { pthread_barrier_destroy(&sleeping_); }
  SliceBarrier(const SliceBarrier&) = delete;
  SliceBarrier& operator=(const SliceBarrier&) = delete;
  void wait() {
    if (wait_ == Wait::Asleep) {
      pthread_barrier_wait(&sleeping_);
      return;
    }
    const int gen = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == 2) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.fetch_add(1, std::memory_order_acq_rel);
      return;
    }
    while (generation_.load(std::memory_order_acquire) == gen)
      if (wait_ == Wait::Spin) __builtin_ia32_pause();
  }

 private:
  const Wait wait_;
  pthread_barrier_t sleeping_;
  std::atomic<int> arrived_{0};
  std::atomic<int> generation_{0};
};

/// One kernel's work: run() does it once on the calling thread, on the
/// first `doubles` of a thread's buffer (0: compute); a kernel that waits
/// runs the compute work in `slices` slices with a wait at `barrier` after
/// each (when given: together, not alone).
struct Kernel {
  const char* name;
  std::size_t doubles;
  Wait wait = Wait::None;
  int chains = 16;  ///< multiply-add chains of the compute work: 16 (compute, sync*) or 128 (fma)
  long reps = 1;
  long slices = 1;
  double compute(long r) const { return chains == 128 ? compute_kernel<128>(r) : compute_kernel<16>(r); }
  double run(std::vector<double>& buf, SliceBarrier* barrier) const {
    if (doubles > 0) return stream_kernel(buf.data(), doubles, reps);
    if (wait == Wait::None) return compute(reps);
    double s = 0.0;
    for (long k = 0; k < slices; ++k) {
      s += compute(reps / slices);
      if (barrier) barrier->wait();
    }
    return s;
  }
};

/// Solo time on `cpu`, or a negative value when the CPU cannot be used.
double solo(const Kernel& k, int cpu, std::vector<double>& buf, Sink& sink) {
  double t = -1.0;
  std::thread th([&] {
    if (!pin_to(cpu)) return;
    const auto t0 = Clock::now();
    sink.value = sink.value + k.run(buf, nullptr);
    t = seconds_since(t0);
  });
  th.join();
  return t;
}

/// Both threads' times together (each pinned, released at once).
void together(const Kernel& k, std::vector<double>& buf0, std::vector<double>& buf1, Sink& sink, double& t0,
              double& t1) {
  pthread_barrier_t start;
  pthread_barrier_init(&start, nullptr, 2);
  SliceBarrier slices(k.wait);
  double r0 = 0.0, r1 = 0.0;
  const auto body = [&](int cpu, std::vector<double>& buf, double& t, double& r) {
    pin_to(cpu);
    pthread_barrier_wait(&start);
    const auto s = Clock::now();
    r = k.run(buf, &slices);
    t = seconds_since(s);
  };
  std::thread a(body, 0, std::ref(buf0), std::ref(t0), std::ref(r0));
  std::thread b(body, 1, std::ref(buf1), std::ref(t1), std::ref(r1));
  a.join();
  b.join();
  pthread_barrier_destroy(&start);
  sink.value = sink.value + r0 + r1;
}

/// The round trip of one cache line between a thread pinned to CPU 0 and
/// one pinned to CPU 1 [ns]: CPU 0 stores k into `ping`, CPU 1 spins until
/// it reads k and stores k into `pong`, CPU 0 spins until it reads that
/// (no PAUSE in the spins, which would add its own latency); the median
/// over `bursts` bursts of `trips` round trips, each burst timed on CPU 0.
/// Two threads of the DEM step move the lines of the particles at their
/// cut between the two cores' caches every step; a move costs about half a
/// round trip when nothing overlaps it. Negative when a CPU cannot be used.
double round_trip_ns(long trips, int bursts) {
  struct alignas(128) Line {  // 128: not even in the adjacent-line prefetcher's pair
    std::atomic<long> value{0};
  };
  Line ping, pong;
  std::atomic<bool> partner_pinned{false};
  const long total = trips * bursts;
  pthread_barrier_t start;
  pthread_barrier_init(&start, nullptr, 2);
  std::thread partner([&] {
    partner_pinned.store(pin_to(1));
    pthread_barrier_wait(&start);
    if (!partner_pinned.load()) return;
    for (long k = 1; k <= total; ++k) {
      long v;
      while ((v = ping.value.load(std::memory_order_acquire)) != k && v >= 0) {
      }
      if (v < 0) return;  // CPU 0 could not be used: stop
      pong.value.store(k, std::memory_order_release);
    }
  });
  std::vector<double> burst_ns;
  std::thread timer([&] {  // a thread of its own: the caller keeps its affinity
    const bool pinned = pin_to(0);
    pthread_barrier_wait(&start);
    if (!(pinned && partner_pinned.load())) {
      ping.value.store(-1, std::memory_order_release);
      return;
    }
    long k = 0;
    for (int b = 0; b < bursts; ++b) {
      const auto t0 = Clock::now();
      for (long i = 0; i < trips; ++i) {
        ping.value.store(++k, std::memory_order_release);
        while (pong.value.load(std::memory_order_acquire) != k) {
        }
      }
      burst_ns.push_back(1e9 * seconds_since(t0) / static_cast<double>(trips));
    }
  });
  partner.join();
  timer.join();
  pthread_barrier_destroy(&start);
  return burst_ns.empty() ? -1.0 : vt::bench::quantile(burst_ns, 0.5);
}

void print_round_trip(int round, double ns) {
  std::printf("%-6d %-8s %8.1f ns round trip of a cache line between CPUs 0 and 1\n", round, "pingpong", ns);
  std::fflush(stdout);
}

std::string read_stat_cpu_line() {
  std::ifstream f("/proc/stat");
  std::string line;
  std::getline(f, line);
  return line;
}

/// A failure at run time (not the arguments'): the reason alone, exit status 1.
int failure(const char* why) {
  std::fprintf(stderr, "host_scaling: %s\n", why);
  return 1;
}

int usage(const char* why) {
  std::fprintf(stderr, "host_scaling: %s\nusage: host_scaling [--rounds R] [--seconds S] | --pingpong [--rounds R]\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 10;
  double seconds = 0.15;
  bool pingpong_only = false;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--pingpong") {
      pingpong_only = true;
    } else if ((arg == "--rounds" || arg == "--seconds") && a + 1 < argc) {
      char* end = nullptr;
      const double v = std::strtod(argv[++a], &end);
      if (*end != '\0' || !(v > 0.0)) return usage((arg + " must be a positive number").c_str());
      if (arg == "--rounds") {
        if (v != static_cast<int>(v)) return usage("--rounds must be a whole number");
        rounds = static_cast<int>(v);
      } else {
        seconds = v;
      }
    } else {
      return usage(("unknown argument '" + arg + "'").c_str());
    }
  }
  if (std::thread::hardware_concurrency() < 2) return usage("needs two CPUs");
  if (pingpong_only) {
    std::vector<double> round_trips;
    for (int r = 1; r <= rounds; ++r) {
      const double rt = round_trip_ns(kRoundTrips, kRoundTripBursts);
      if (rt < 0.0) return failure("cannot run on CPUs 0 and 1 (taskset?)");
      round_trips.push_back(rt);
      print_round_trip(r, rt);
    }
    std::printf("median_round_trip_ns: %.1f\n", vt::bench::quantile(round_trips, 0.5));
    return 0;
  }

  std::vector<Kernel> kernels{{"compute", 0},
                              {"fma", 0, Wait::None, 128},
                              {"sync", 0, Wait::Spin},
                              {"syncnp", 0, Wait::SpinNoPause},
                              {"syncblk", 0, Wait::Asleep},
                              {"cache", (6u << 20) / sizeof(double)},
                              {"memory", (96u << 20) / sizeof(double)}};
  std::vector<double> buf0((96u << 20) / sizeof(double), 1.0), buf1(buf0.size(), 1.0);
  Sink sink;
  // Size each kernel without waits to about `seconds` alone on CPU 0.
  for (Kernel& k : kernels) {
    if (k.wait != Wait::None) continue;
    for (;;) {
      const double t = solo(k, 0, buf0, sink);
      if (t < 0.0) return failure("cannot run on CPU 0 (taskset?)");
      if (t >= 0.02) {
        k.reps = std::max<long>(1, static_cast<long>(k.reps * seconds / t));
        break;
      }
      k.reps *= 4;
    }
  }
  // The kernels that wait: compute's work in slices of about kSliceSeconds
  // (a slice runs slower than its share of one call, so the count comes
  // from a timing of the sliced work; alone, no barrier is waited at).
  const long compute_reps =
      std::find_if(kernels.begin(), kernels.end(), [](const Kernel& k) { return std::strcmp(k.name, "compute") == 0; })
          ->reps;
  Kernel sliced = {"sliced", 0, Wait::Spin};
  sliced.reps = compute_reps;
  sliced.slices = std::max(1L, static_cast<long>(seconds / kSliceSeconds));
  sliced.reps -= sliced.reps % sliced.slices;
  const long slices = std::max(1L, static_cast<long>(solo(sliced, 0, buf0, sink) / kSliceSeconds));
  for (Kernel& k : kernels) {
    if (k.wait == Wait::None) continue;
    k.slices = slices;
    k.reps = compute_reps - compute_reps % slices;
  }

  std::printf("# host_scaling: %d rounds; S = (t_solo0 + t_solo1) / max(t_0, t_1) (2: two CPUs as fast together "
              "as alone)\n",
              rounds);
  std::printf("%-6s %-8s %8s %8s %8s %8s %8s %6s %7s\n", "round", "kernel", "solo0_s", "solo1_s", "tog0_s",
              "tog1_s", "slow0/1", "S", "steal%");
  std::vector<std::vector<double>> s_of(kernels.size());
  std::vector<double> round_trips;
  for (int r = 1; r <= rounds; ++r) {
    for (std::size_t ki = 0; ki < kernels.size(); ++ki) {
      const Kernel& k = kernels[ki];
      const std::string stat0 = read_stat_cpu_line();
      const double s0 = solo(k, 0, buf0, sink);
      const double s1 = solo(k, 1, buf1, sink);
      if (s0 < 0.0 || s1 < 0.0) return failure("cannot run on CPUs 0 and 1 (taskset?)");
      double t0 = 0.0, t1 = 0.0;
      together(k, buf0, buf1, sink, t0, t1);
      const std::optional<double> steal = vt::dem::steal_share(stat0, read_stat_cpu_line());
      const double scaling = (s0 + s1) / std::max(t0, t1);
      s_of[ki].push_back(scaling);
      std::printf("%-6d %-8s %8.4f %8.4f %8.4f %8.4f %4.2f/%4.2f %6.3f %7.2f\n", r, k.name, s0, s1, t0, t1, t0 / s0,
                  t1 / s1, scaling, steal ? 100.0 * *steal : -1.0);
    }
    const double rt = round_trip_ns(kRoundTrips, kRoundTripBursts);
    if (rt < 0.0) return failure("cannot run on CPUs 0 and 1 (taskset?)");
    round_trips.push_back(rt);
    print_round_trip(r, rt);
  }
  for (std::size_t ki = 0; ki < kernels.size(); ++ki)
    std::printf("median_S_%s: %.3f\n", kernels[ki].name, vt::bench::quantile(s_of[ki], 0.5));
  std::printf("median_round_trip_ns: %.1f\n", vt::bench::quantile(round_trips, 0.5));
  return sink.value == 12345.678 ? 1 : 0;
}
