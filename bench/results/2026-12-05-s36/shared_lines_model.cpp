// Session 36 experiment E2 (bench/results/2026-12-05-s36/experiments.txt), not built by the project:
// written against commit a095390 (SplitSums with edge particles and tails, since replaced by ghosts);
// g++ -O2 -std=c++17 -fopenmp -march=native -Iinclude -I/usr/include/eigen3 -I/usr/include/hdf5/serial
//   shared_lines_model.cpp -Lbuild/devel/lib -lvt_dem -lvt_io
// Model: cache lines that change cores per step on two threads (MESI-like, infinite caches).
#include <omp.h>
#include <cstdio>
#include <map>
#include <unordered_map>
#include <string>
#include <vector>
#include <cstdint>
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/io/sample_file.h"
using namespace vt::dem;
enum Arr { FRAC, VEL, OMG, RAD, FOUT, TOUT, STATE, SPRING, ACTIVE, NARR };
const char* an[] = {"frac","vel","omg","rad","fout","tout","state","spring","active"};
const int esz[] = {24,24,24,8,24,24,64,24,1};
struct LineSt { std::uint8_t sharers = 0; std::int8_t mod = -1; };
struct Model {
  std::unordered_map<std::uint64_t, LineSt> lines;
  long cnt[NARR][3] = {}; // 0 read dirty from other, 1 read clean held by other, 2 write invalidating other
  bool counting = false;
  std::uint64_t key(int a, long idx) { return (std::uint64_t(a) << 56) | std::uint64_t(idx * esz[a] / 64); }
  void rd(int c, int a, long idx) {
    LineSt& l = lines[key(a, idx)]; int o = 1 - c;
    if (l.sharers & (1 << c)) return;
    if (l.mod == o) { if (counting) cnt[a][0]++; l.mod = -1; }
    else if (l.sharers & (1 << o)) { if (counting) cnt[a][1]++; }
    l.sharers |= (1 << c);
  }
  void wr(int c, int a, long idx) {
    LineSt& l = lines[key(a, idx)]; int o = 1 - c;
    if (l.mod == c) return;
    if ((l.sharers & (1 << o)) || l.mod == o) { if (counting) cnt[a][2]++; }
    l.sharers = 1 << c; l.mod = c;
  }
};
int main(int argc, char** argv) {
  std::string sample = argc > 1 ? argv[1] : "config/samples/dense_1000.h5";
  int kx = 3, ky = 2, kz = 2; if (argc > 2) sscanf(argv[2], "%dx%dx%d", &kx, &ky, &kz);
  int byrun = argc > 3 ? atoi(argv[3]) : 0;
  SimulationState st = tile_periodic(vt::io::read_sample(sample), kx, ky, kz);
  spatial_sort(st);
  Simulation sim(st);
  omp_set_num_threads(2);
  for (int s = 0; s < 400; ++s) sim.step();
  const NeighborList& list = sim.neighbor_list();
  const ThreadRuns& runs = sim.thread_runs();
  SplitSums split; split.prepare(list, sim.particles().size(), runs);
  const int n = (int)sim.particles().size();
  auto [a0, a1] = runs.run(0); auto [b0, b1] = runs.run(1);
  int cut = std::min(n, a1 * kChunkSize);
  printf("n %d runs [0,%d) [%d,%d) particles; edges %zu tails %zu\n", n, cut, cut, n, split.edge_count(), split.tail_count());
  const auto& off = list.offsets(); const auto& own = list.owners(); const auto& par = list.pairs().partner;
  const auto& act = list.pairs().active; const auto& goff = list.gather_offsets(); const auto& gcode = list.gather_codes();
  auto run_of = [&](int p) { return p < cut ? 0 : 1; };
  long crossing = 0, crossing_contacts = 0;
  for (size_t e = 0; e < par.size(); ++e) if (run_of(own[e]) != run_of(par[e])) { crossing++; if (act[e]) crossing_contacts++; }
  printf("entries %zu crossing %ld (contacts %ld)\n", par.size(), crossing, crossing_contacts);
  Model m;
  for (int step = 0; step < 3; ++step) {
    m.counting = step == 2;
    // P
    for (int t = 0; t < 2; ++t) {
      int i0 = t ? cut : 0, i1 = t ? n : cut;
      for (int i = i0; i < i1; ++i) { m.wr(t, FOUT, i); m.wr(t, TOUT, i); }
      for (int i = i0; i < i1; ++i) {
        m.rd(t, FRAC, i); m.rd(t, RAD, i);
        for (int e = off[i]; e < off[i + 1]; ++e) {
          int j = par[e];
          m.rd(t, FRAC, j); m.rd(t, RAD, j); m.rd(t, VEL, j); m.rd(t, OMG, j); m.wr(t, ACTIVE, e);
          if (act[e]) {
            m.rd(t, VEL, i); m.rd(t, OMG, i); m.wr(t, STATE, e); m.wr(t, SPRING, e);
            m.wr(t, FOUT, i); m.wr(t, TOUT, i);
            if (run_of(j) == t) { m.wr(t, FOUT, j); m.wr(t, TOUT, j); }
          }
        }
      }
    }
    // C
    for (int t = 0; t < 2; ++t) {
      for (int tt = 0; tt < 2; ++tt) {
        for (int i : split.edge_particles(tt)) {
          int c = byrun ? run_of(i) : tt; if (c != t) continue;
          for (int g = goff[i]; g < goff[i + 1]; ++g) m.rd(c, STATE, gcode[g] >> 2);
          m.rd(c, RAD, i); m.wr(c, FOUT, i); m.wr(c, TOUT, i);
        }
        for (const auto& x : split.edge_tails(tt)) {
          int i = x.particle; int c = byrun ? run_of(i) : tt; if (c != t) continue;
          m.rd(c, FOUT, i); m.rd(c, TOUT, i);
          for (int g = x.slot; g < goff[i + 1]; ++g) m.rd(c, STATE, gcode[g] >> 2);
          m.wr(c, FOUT, i); m.wr(c, TOUT, i);
        }
      }
    }
    // I
    for (int t = 0; t < 2; ++t) {
      int i0 = t ? cut : 0, i1 = t ? n : cut;
      for (int i = i0; i < i1; ++i) { m.rd(t, FOUT, i); m.rd(t, TOUT, i); m.wr(t, VEL, i); m.wr(t, OMG, i); m.wr(t, FRAC, i); }
    }
  }
  long tot[3] = {};
  printf("%-8s %10s %10s %10s\n", "array", "rd_dirty", "rd_clean", "wr_inval");
  for (int a = 0; a < NARR; ++a) { printf("%-8s %10ld %10ld %10ld\n", an[a], m.cnt[a][0], m.cnt[a][1], m.cnt[a][2]); for (int k = 0; k < 3; ++k) tot[k] += m.cnt[a][k]; }
  printf("%-8s %10ld %10ld %10ld  (per cut particle: %.2f %.2f %.2f)\n", "total", tot[0], tot[1], tot[2],
    tot[0] / double(split.edge_count() + split.tail_count()), tot[1] / double(split.edge_count() + split.tail_count()), tot[2] / double(split.edge_count() + split.tail_count()));
}
