#include "virtual_triaxial/dem/split_sums.h"

#include <algorithm>
#include <cstdint>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void SplitSums::prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs) {
  if (current(list, n, runs)) return;
  list_ = &list;
  build_ = list.rebuild_count();
  n_ = n;
  runs_version_ = runs.version();
  threads_ = runs.threads();
  const auto t_count = static_cast<std::size_t>(runs.threads());
  std::vector<int> run_of_chunk(static_cast<std::size_t>(chunk_count(n)));
  for (int t = 0; t < runs.threads(); ++t) {
    const auto [c0, c1] = runs.run(t);
    for (std::int32_t c = c0; c < c1; ++c) run_of_chunk[static_cast<std::size_t>(c)] = t;
  }
  const auto run_of = [&](std::int32_t p) { return run_of_chunk[static_cast<std::size_t>(p / kChunkSize)]; };
  edge_.assign(t_count, {});
  tail_.assign(t_count, {});
  ghost_.assign(t_count, {});
  ghost_lower_.assign(t_count, 0);
  edges_ = tails_ = ghosts_ = cut_ = 0;
  if (!list.has_spheroids()) {
    // spheres: every crossing entry a ghost of its partner's thread, those
    // owned in lower runs first (entries ascending, so list order)
    const std::vector<std::int32_t>& partner = list.pairs().partner;
    const std::vector<std::int32_t>& owners = list.owners();
    std::vector<std::vector<std::int32_t>> higher(t_count);
    std::vector<std::uint8_t> at_cut(n, 0);
    for (std::size_t e = 0; e < partner.size(); ++e) {
      const int to = run_of(owners[e]), tp = run_of(partner[e]);
      if (to == tp) continue;
      (to < tp ? ghost_ : higher)[static_cast<std::size_t>(tp)].push_back(static_cast<std::int32_t>(e));
      ++ghosts_;
      std::uint8_t& flag = at_cut[static_cast<std::size_t>(partner[e])];
      cut_ += flag == 0 ? 1 : 0;
      flag = 1;
    }
    for (std::size_t t = 0; t < t_count; ++t) {
      ghost_lower_[t] = ghost_[t].size();
      ghost_[t].insert(ghost_[t].end(), higher[t].begin(), higher[t].end());
    }
    return;
  }
  // the partners of pairs owned in other runs, flagged 1 (some owned in a
  // lower run) and 2 (some in a higher run)
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  const std::vector<std::int32_t>& owners = list.owners();
  std::vector<std::uint8_t> from(n, 0);
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const int to = run_of(owners[e]), tp = run_of(partner[e]);
    if (to != tp) from[static_cast<std::size_t>(partner[e])] |= to < tp ? 1 : 2;
  }
  // the completions in particle order (so a thread's share is mostly its
  // own run, whose sums it integrates next)
  const std::int32_t* goff = list.gather_offsets().data();
  const std::int32_t* gcode = list.gather_codes().data();
  std::vector<Tail> items;  // slot -1: an edge particle, gathered again from its first slot
  std::int64_t total = 0;   // slots read by all completions
  for (std::int32_t j = 0; j < static_cast<std::int32_t>(n); ++j) {
    const std::uint8_t f = from[static_cast<std::size_t>(j)];
    if ((f & 1) != 0) {
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
  std::int64_t done = 0;
  for (const Tail& x : items) {
    const auto share = std::min<std::size_t>(
        t_count - 1, static_cast<std::size_t>(done * static_cast<std::int64_t>(t_count) / std::max<std::int64_t>(total, 1)));
    const bool edge = x.slot < 0;
    done += goff[x.particle + 1] - (edge ? goff[x.particle] : x.slot);
    if (edge) {
      edge_[share].push_back(x.particle);
      ++edges_;
    } else {
      tail_[share].push_back(x);
      ++tails_;
    }
  }
  cut_ = edges_ + tails_;
}

}  // namespace vt::dem
