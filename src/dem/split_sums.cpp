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
  // every crossing entry a ghost of its partner's thread, those owned in
  // lower runs first (entries ascending, so list order)
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  const std::vector<std::int32_t>& owners = list.owners();
  ghost_.assign(t_count, {});
  ghost_lower_.assign(t_count, 0);
  ghosts_ = cut_ = 0;
  std::vector<std::vector<std::int32_t>> higher(t_count);
  std::vector<std::uint8_t> at_cut(n, 0);
  shared_chunk_.assign(run_of_chunk.size(), 0);
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const int to = run_of(owners[e]), tp = run_of(partner[e]);
    if (to == tp) continue;
    (to < tp ? ghost_ : higher)[static_cast<std::size_t>(tp)].push_back(static_cast<std::int32_t>(e));
    ++ghosts_;
    shared_chunk_[static_cast<std::size_t>(owners[e] / kChunkSize)] = 1;
    shared_chunk_[static_cast<std::size_t>(partner[e] / kChunkSize)] = 1;
    std::uint8_t& flag = at_cut[static_cast<std::size_t>(partner[e])];
    cut_ += flag == 0 ? 1 : 0;
    flag = 1;
  }
  for (std::size_t t = 0; t < t_count; ++t) {
    ghost_lower_[t] = ghost_[t].size();
    ghost_[t].insert(ghost_[t].end(), higher[t].begin(), higher[t].end());
  }
}

}  // namespace vt::dem
