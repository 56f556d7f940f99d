#include "virtual_triaxial/dem/split_sums.h"

#include <algorithm>
#include <cstdint>

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
    // completions after the barrier, in particle order (so a thread's share
    // is mostly its own run, whose sums it integrates next): the partners
    // of pairs owned in other runs, flagged 1 (some owned in a lower run)
    // and 2 (some in a higher run)
    std::vector<std::uint8_t> from(n, 0);
    for (std::size_t t = 0; t < t_count; ++t) {
      for (const Ghost& x : before_[t]) from[static_cast<std::size_t>(partner[static_cast<std::size_t>(x.entry)])] |= 1;
      for (const Ghost& x : after_[t]) from[static_cast<std::size_t>(partner[static_cast<std::size_t>(x.entry)])] |= 2;
    }
    const std::int32_t* goff = list.gather_offsets().data();
    const std::int32_t* gcode = list.gather_codes().data();
    std::vector<Tail> items;  // slot -1: an edge particle, gathered again from its first slot
    std::int64_t total = 0;   // slots read by all completions
    for (std::int32_t j = 0; j < static_cast<std::int32_t>(n); ++j) {
      const std::uint8_t f = from[static_cast<std::size_t>(j)];
      if ((f & 1) != 0 && list.has_spheroids()) {
        items.push_back({j, -1});
        total += goff[j + 1] - goff[j];
      } else if ((f & 2) != 0) {
        std::int32_t g = goff[j];  // the first slot owned in a higher run (one exists)
        while ((gcode[g] & 2) != 0 || run_of(owners[static_cast<std::size_t>(gcode[g] >> 2)]) <= run_of(j)) ++g;
        items.push_back({j, g});
        total += goff[j + 1] - g;
      }
    }
    // thread shares: consecutive items, cut by the slots read before them
    edge_.assign(t_count, {});
    tail_.assign(t_count, {});
    std::int64_t done = 0;
    for (const Tail& x : items) {
      const auto share = std::min<std::size_t>(
          t_count - 1, static_cast<std::size_t>(done * static_cast<std::int64_t>(t_count) / std::max<std::int64_t>(total, 1)));
      const bool edge = x.slot < 0;
      done += goff[x.particle + 1] - (edge ? goff[x.particle] : x.slot);
      if (edge) {
        edge_[share].push_back(x.particle);
      } else {
        tail_[share].push_back(x);
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
