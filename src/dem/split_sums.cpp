#include "virtual_triaxial/dem/split_sums.h"

#include <algorithm>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void SplitSums::prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs) {
  if (list_ == &list && build_ == list.rebuild_count() && n_ == n && runs_version_ == runs.version()) return;
  list_ = &list;
  build_ = list.rebuild_count();
  n_ = n;
  runs_version_ = runs.version();
  const int threads = runs.threads();
  const std::int32_t nchunks = chunk_count(n);
  const auto t_count = static_cast<std::size_t>(threads);
  // run of each chunk
  std::vector<int> run_of_chunk(static_cast<std::size_t>(nchunks));
  for (int t = 0; t < threads; ++t) {
    const auto [c0, c1] = runs.run(t);
    for (std::int32_t c = c0; c < c1; ++c) run_of_chunk[static_cast<std::size_t>(c)] = t;
  }
  const auto run_of = [&](std::int32_t p) { return run_of_chunk[static_cast<std::size_t>(p / kChunkSize)]; };
  sole_.assign(n, 1);
  foreign_.assign(t_count, {});
  const std::vector<std::int32_t>& owners = list.owners();
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const int ti = run_of(owners[e]);
    const std::int32_t j = partner[e];
    if (ti == run_of(j)) continue;
    sole_[static_cast<std::size_t>(j)] = 0;
    foreign_[static_cast<std::size_t>(ti)].push_back(j);
  }
  for (std::vector<std::int32_t>& f : foreign_) {
    std::sort(f.begin(), f.end());
    f.erase(std::unique(f.begin(), f.end()), f.end());
  }
  gathered_ = static_cast<std::size_t>(std::count(sole_.begin(), sole_.end(), std::uint8_t{0}));
  force_.resize(t_count);
  torque_.resize(t_count);
  for (std::size_t t = 0; t < t_count; ++t) {
    force_[t].resize(n);
    torque_[t].resize(n);
  }
}

}  // namespace vt::dem
