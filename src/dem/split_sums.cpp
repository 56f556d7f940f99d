#include "virtual_triaxial/dem/split_sums.h"

#include <algorithm>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void SplitSums::prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs, std::int64_t stamp) {
  const bool plan = serves(list, n, runs);
  const bool follows = plan && stamp == stamp_ + 1;
  stamp_ = stamp - 1;  // finish_step(stamp) makes it stamp
  if (follows) return;
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  if (!plan) {
    list_ = &list;
    build_ = list.rebuild_count();
    n_ = n;
    runs_version_ = runs.version();
    const auto t_count = static_cast<std::size_t>(runs.threads());
    std::vector<int> run_of_chunk(static_cast<std::size_t>(chunk_count(n)));
    for (int t = 0; t < runs.threads(); ++t) {
      const auto [c0, c1] = runs.run(t);
      for (std::int32_t c = c0; c < c1; ++c) run_of_chunk[static_cast<std::size_t>(c)] = t;
    }
    const auto run_of = [&](std::int32_t p) { return run_of_chunk[static_cast<std::size_t>(p / kChunkSize)]; };
    before_.assign(t_count, {});
    after_.assign(t_count, {});
    boundary_.assign(t_count, {});
    const std::vector<std::int32_t>& owners = list.owners();
    for (std::size_t e = 0; e < partner.size(); ++e) {  // ascending: every list stays sorted
      const int to = run_of(owners[e]), tp = run_of(partner[e]);
      if (to < tp) boundary_[static_cast<std::size_t>(to)].push_back(static_cast<std::int32_t>(e));
      if (to > tp) after_[static_cast<std::size_t>(tp)].push_back({static_cast<std::int32_t>(e), -1});
    }
    // slots: the boundary entries run by run, each run's in entry order
    boundary_slot_.assign(t_count, 0);
    std::int32_t slot = 0;
    for (std::size_t t = 0; t < t_count; ++t) {
      boundary_slot_[t] = slot;
      for (const std::int32_t e : boundary_[t])
        before_[static_cast<std::size_t>(run_of(partner[static_cast<std::size_t>(e)]))].push_back({e, slot++});
    }
    // before_ filled run by run of the owner: entry order too, since runs
    // are ranges of owners
    ghosts_ = static_cast<std::size_t>(slot);
    // completions after the barrier: edge particles (spheroid lists; the
    // sphere path has ghosts) and tails, per run, then shared by slots read
    edge_.assign(t_count, {});
    tail_.assign(t_count, {});
    const std::int32_t* goff = list.gather_offsets().data();
    const std::int32_t* gcode = list.gather_codes().data();
    const auto partners_of = [&](const std::vector<Ghost>& ghosts) {
      std::vector<std::int32_t> p;
      for (const Ghost& x : ghosts) p.push_back(partner[static_cast<std::size_t>(x.entry)]);
      std::sort(p.begin(), p.end());
      p.erase(std::unique(p.begin(), p.end()), p.end());
      return p;
    };
    std::vector<std::vector<std::int32_t>> edge_run(t_count);
    std::vector<std::vector<Tail>> tail_run(t_count);
    std::int64_t total = 0;  // slots read by all completions
    for (std::size_t t = 0; t < t_count; ++t) {
      if (list.has_spheroids()) edge_run[t] = partners_of(before_[t]);
      for (const std::int32_t j : edge_run[t]) total += goff[j + 1] - goff[j];
      for (const std::int32_t j : partners_of(after_[t])) {
        if (std::binary_search(edge_run[t].begin(), edge_run[t].end(), j)) continue;
        std::int32_t g = goff[j];  // the first slot owned in a higher run (one exists)
        while ((gcode[g] & 2) != 0 || run_of(owners[static_cast<std::size_t>(gcode[g] >> 2)]) <= static_cast<int>(t))
          ++g;
        tail_run[t].push_back({j, g});
        total += goff[j + 1] - g;
      }
    }
    // thread shares: the completions in particle order (so mostly of the
    // thread's own run, whose sums it integrates next), cut into
    // consecutive parts by the slots read before them
    std::int64_t done = 0;
    const auto share = [&](std::int64_t cost) {
      const auto s = static_cast<std::size_t>(done * static_cast<std::int64_t>(t_count) / std::max<std::int64_t>(total, 1));
      done += cost;
      return std::min(s, t_count - 1);
    };
    for (std::size_t t = 0; t < t_count; ++t) {
      auto edge = edge_run[t].begin();
      auto tail = tail_run[t].begin();
      while (edge != edge_run[t].end() || tail != tail_run[t].end()) {
        if (tail == tail_run[t].end() || (edge != edge_run[t].end() && *edge < tail->particle)) {
          edge_[share(goff[*edge + 1] - goff[*edge])].push_back(*edge);
          ++edge;
        } else {
          tail_[share(goff[tail->particle + 1] - tail->slot)].push_back(*tail);
          ++tail;
        }
      }
    }
    for (std::vector<Vec3>& s : spring_) s.assign(ghosts_, Vec3{});
  }
  const std::vector<Vec3>& spring = list.pairs().spring;
  for (std::size_t t = 0; t < boundary_.size(); ++t) {
    Vec3* out = spring_[read_].data() + boundary_slot_[t];
    for (const std::int32_t e : boundary_[t]) *out++ = spring[static_cast<std::size_t>(e)];
  }
}

void SplitSums::finish_step(std::int64_t stamp) {
  stamp_ = stamp;
  read_ = 1 - read_;
}

}  // namespace vt::dem
