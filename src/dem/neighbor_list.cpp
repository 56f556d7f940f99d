#include "virtual_triaxial/dem/neighbor_list.h"

#include "virtual_triaxial/dem/huge_pages.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace vt::dem {

namespace {
constexpr std::int32_t kChunk = 512;

int wrap_bin(int b, int n) { return b < 0 ? b + n : (b >= n ? b - n : b); }
}  // namespace

void PairData::resize(std::size_t n, bool spheroids) {
  // Fresh arrays of a rebuild: huge pages before the first write.
  reserve_huge(partner, n);
  reserve_huge(spring, n);
  reserve_huge(state, n);
  if (spheroids) reserve_huge(spheroid, n);
  partner.resize(n);
  spring.resize(n);
  state.resize(n);
  active.resize(n, 0);
  spheroid.resize(spheroids ? n : 0);
}

void NeighborList::build_bins(const Particles& p, const PeriodicCell& cell, double cutoff) {
  const Vec3 h = cell.heights();
  for (int a = 0; a < 3; ++a) nbins_[a] = static_cast<int>(std::floor(h[a] / cutoff));
  const bool use_bins = nbins_[0] >= 3 && nbins_[1] >= 3 && nbins_[2] >= 3;
  if (!use_bins) {
    nbins_[0] = nbins_[1] = nbins_[2] = 1;
  }
  const std::size_t nb = static_cast<std::size_t>(nbins_[0]) * nbins_[1] * nbins_[2];
  const std::size_t n = p.size();
  particle_bin_.resize(n);
  bin_start_.assign(nb + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& s = p.frac[i];
    int b[3];
    for (int a = 0; a < 3; ++a) {
      b[a] = static_cast<int>(s[a] * nbins_[a]);
      b[a] = std::min(std::max(b[a], 0), nbins_[a] - 1);
    }
    const std::int32_t idx = (b[2] * nbins_[1] + b[1]) * nbins_[0] + b[0];
    particle_bin_[i] = idx;
    ++bin_start_[idx + 1];
  }
  for (std::size_t b = 0; b < nb; ++b) bin_start_[b + 1] += bin_start_[b];
  bin_particles_.resize(n);
  std::vector<std::int32_t> fill(bin_start_.begin(), bin_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) bin_particles_[fill[particle_bin_[i]]++] = static_cast<std::int32_t>(i);
}

void NeighborList::collect_candidates(const Particles& p, const PeriodicCell& cell,
                                      std::vector<std::vector<std::int32_t>>& chunks) const {
  const std::int32_t n = static_cast<std::int32_t>(p.size());
  const std::int32_t nchunks = (n + kChunk - 1) / kChunk;
  chunks.assign(static_cast<std::size_t>(nchunks), {});
  const bool brute = nbins_[0] == 1;
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int32_t c = 0; c < nchunks; ++c) {
    std::vector<std::int32_t>& out = chunks[static_cast<std::size_t>(c)];
    std::vector<std::pair<std::int64_t, std::int32_t>> local;
    const std::int32_t i_end = std::min(n, (c + 1) * kChunk);
    for (std::int32_t i = c * kChunk; i < i_end; ++i) {
      local.clear();
      const std::int64_t idi = p.id[i];
      const Vec3 si = p.frac[i];
      const double ri = p.semi_axes[i].x + skin_;
      auto consider = [&](std::int32_t j) {
        if (p.id[j] <= idi) return;
        const double reach = ri + p.semi_axes[j].x;
        const Vec3 d = cell.branch(si, p.frac[j]);
        if (norm2(d) < reach * reach) local.emplace_back(p.id[j], j);
      };
      if (brute) {
        for (std::int32_t j = 0; j < n; ++j) consider(j);
      } else {
        const std::int32_t b = particle_bin_[i];
        const int bx = b % nbins_[0], by = (b / nbins_[0]) % nbins_[1], bz = b / (nbins_[0] * nbins_[1]);
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int nbx = wrap_bin(bx + dx, nbins_[0]), nby = wrap_bin(by + dy, nbins_[1]),
                        nbz = wrap_bin(bz + dz, nbins_[2]);
              const std::int32_t nbidx = (nbz * nbins_[1] + nby) * nbins_[0] + nbx;
              for (std::int32_t k = bin_start_[nbidx]; k < bin_start_[nbidx + 1]; ++k)
                consider(bin_particles_[k]);
            }
      }
      std::sort(local.begin(), local.end());
      out.push_back(static_cast<std::int32_t>(local.size()));
      for (const auto& e : local) out.push_back(e.second);
    }
  }
}

void NeighborList::build(const Particles& p, const PeriodicCell& cell) {
  const std::int32_t n = static_cast<std::int32_t>(p.size());
  cutoff_max_ = 2.0 * p.max_bounding_radius() + skin_;
  const Vec3 h = cell.heights();
  const double hmin = std::min(h.x, std::min(h.y, h.z));
  if (!(cutoff_max_ < 0.5 * hmin))
    throw std::runtime_error("cell too small: the smallest cell height (" + std::to_string(hmin) +
                             " m) must exceed twice the neighbour cutoff (" +
                             std::to_string(cutoff_max_) + " m)");
  build_bins(p, cell, cutoff_max_);
  std::vector<std::vector<std::int32_t>> chunks;
  collect_candidates(p, cell, chunks);

  // CSR offsets, then entries; carry springs over by merging on partner id.
  std::vector<std::int32_t> offsets(static_cast<std::size_t>(n) + 1, 0);
  {
    std::int32_t i = 0;
    std::int64_t total = 0;  // entries are indexed by int32
    for (const auto& ch : chunks)
      for (std::size_t k = 0; k < ch.size(); k += static_cast<std::size_t>(ch[k]) + 1, ++i) {
        total += ch[k];
        if (total > INT32_MAX) throw std::runtime_error("neighbour list: more than 2^31 - 1 pairs are not supported");
        offsets[static_cast<std::size_t>(i) + 1] = static_cast<std::int32_t>(total);
      }
  }
  const bool spheroids = p.has_spheroids();
  PairData next;
  next.resize(static_cast<std::size_t>(offsets[static_cast<std::size_t>(n)]), spheroids);
  const bool carry = built_ && offsets_.size() == offsets.size();
  const bool carry_spheroid = carry && spheroids && spheroids_;
  {
    std::int32_t i = 0;
    for (const auto& ch : chunks) {
      for (std::size_t k = 0; k < ch.size(); ++i) {
        const std::int32_t cnt = ch[k];
        std::int32_t e = offsets[static_cast<std::size_t>(i)];
        std::int32_t o = carry ? offsets_[static_cast<std::size_t>(i)] : 0;
        const std::int32_t o_end = carry ? offsets_[static_cast<std::size_t>(i) + 1] : 0;
        for (std::int32_t m = 0; m < cnt; ++m, ++e) {
          const std::int32_t j = ch[k + 1 + static_cast<std::size_t>(m)];
          next.partner[e] = j;
          const std::int64_t idj = p.id[j];
          while (o < o_end && p.id[pairs_.partner[o]] < idj) ++o;
          if (o < o_end && pairs_.partner[o] == j) {
            next.spring[e] = pairs_.spring[o];
            next.state[e] = pairs_.state[o];
            next.active[e] = pairs_.active[o];
            if (carry_spheroid) next.spheroid[e] = pairs_.spheroid[o];
          }
        }
        k += static_cast<std::size_t>(cnt) + 1;
      }
    }
  }
  offsets_.swap(offsets);
  pairs_ = std::move(next);
  spheroids_ = spheroids;
  build_owners(p);
  frac_at_build_ = p.frac;
  if (rebuilds_ == 0) collapse_huge(frac_at_build_);
  h_at_build_inv_ = cell.h_inverse();
  built_ = true;
  ++rebuilds_;
}

void NeighborList::build_owners(const Particles& p) {
  const std::size_t n = p.size();
  const std::size_t npairs = pairs_.size();
  reserve_huge(owners_, npairs + npairs / 8);
  owners_.resize(npairs);
  for (std::size_t i = 0; i < n; ++i)
    std::fill(owners_.begin() + offsets_[i], owners_.begin() + offsets_[i + 1], static_cast<std::int32_t>(i));
}

double NeighborList::max_displacement2(const Particles& p, const PeriodicCell& cell) const {
  double m = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 ds = PeriodicCell::minimum_image(p.frac[i] - frac_at_build_[i]);
    m = std::max(m, norm2(cell.h() * ds));
  }
  return m;
}

bool NeighborList::needs_rebuild(const Particles& p, const PeriodicCell& cell) const {
  if (!built_ || frac_at_build_.size() != p.size()) return true;
  return stale(max_displacement2(p, cell), cell);
}

bool NeighborList::stale(double max_disp2, const PeriodicCell& cell) const {
  const double dev = frobenius_distance(cell.h() * h_at_build_inv_, 1.0);  // ||H H_build^-1 - I||_F
  return 2.0 * std::sqrt(max_disp2) + dev * cutoff_max_ > skin_;
}

std::vector<ContactHistory> NeighborList::histories(const Particles& p) const {
  std::vector<ContactHistory> out;
  histories_into(p, out);
  return out;
}

namespace {
/// The histories' order: by (id_a, id_b) (for histories and their sort keys).
template <class T>
bool ids_before(const T& a, const T& b) {
  return a.id_a != b.id_a ? a.id_a < b.id_a : a.id_b < b.id_b;
}
}  // namespace

void sort_histories(std::vector<ContactHistory>& h) { std::sort(h.begin(), h.end(), ids_before<ContactHistory>); }

void NeighborList::histories_into(const Particles& p, std::vector<ContactHistory>& out, bool sorted) const {
  const auto kept = [this](std::int32_t e) {
    const Vec3& s = pairs_.spring[e];
    return pairs_.half_overlap[e] != 0.0 || s.x != 0.0 || s.y != 0.0 || s.z != 0.0 ||
           (spheroids_ && pairs_.spheroid[e].cache.valid);
  };
  // Ordered by (id_a, id_b), unique keys: the keys and entries are sorted
  // first and each history is written once in that order (a history is
  // large, and the runners take the state at every sample).
  std::vector<HistoryKey>& keys = history_keys_;
  keys.clear();
  for (std::size_t i = 0; i + 1 < offsets_.size(); ++i)
    for (std::int32_t e = offsets_[i]; e < offsets_[i + 1]; ++e)
      if (kept(e)) keys.push_back({p.id[i], p.id[pairs_.partner[e]], e});
  if (sorted) std::sort(keys.begin(), keys.end(), ids_before<HistoryKey>);
  out.clear();
  for (const HistoryKey& k : keys) {
    const bool cached = spheroids_ && pairs_.spheroid[k.entry].cache.valid;
    out.push_back({k.id_a, k.id_b, pairs_.spring[k.entry], cached ? pairs_.spheroid[k.entry].cache : SpheroidContactCache{}});
  }
}

std::size_t NeighborList::restore(const Particles& p, const std::vector<ContactHistory>& hist) {
  std::unordered_map<std::int64_t, std::int32_t> index;
  index.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) index.emplace(p.id[i], static_cast<std::int32_t>(i));
  std::size_t missing = 0;
  for (const ContactHistory& h : hist) {
    auto it = index.find(h.id_a);
    bool found = false;
    if (it != index.end()) {
      const std::size_t i = static_cast<std::size_t>(it->second);
      for (std::int32_t e = offsets_[i]; e < offsets_[i + 1]; ++e)
        if (p.id[pairs_.partner[e]] == h.id_b) {
          pairs_.spring[e] = h.spring;
          if (spheroids_) pairs_.spheroid[e].cache = h.cache;
          // Mark as "in contact at the last evaluation" so that the next force
          // evaluation clears the spring if the pair has separated, exactly
          // as an uninterrupted run does. Every entry's flag is rewritten by
          // the force evaluation before anything reads it as an overlap.
          pairs_.state[e].half_overlap = -1.0;
          pairs_.active[e] = 1;
          found = true;
          break;
        }
    }
    if (!found) ++missing;
  }
  return missing;
}

}  // namespace vt::dem
