#include "virtual_triaxial/dem/contact_forces.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "pair_kernel.h"

namespace vt::dem {

void ContactSums::add(const ContactSums& o) {
  virial = virial + o.virial;
  elastic_energy += o.elastic_energy;
  friction_dissipation += o.friction_dissipation;
  viscous_dissipation += o.viscous_dissipation;
  max_overlap_ratio = std::max(max_overlap_ratio, o.max_overlap_ratio);
  contacts += o.contacts;
  sliding += o.sliding;
  sum_force += o.sum_force;
  sum_force2 += o.sum_force2;
  axis_stiffness_sum += o.axis_stiffness_sum;
  spheroid.add(o.spheroid);
}

void ContactForces::Scratch::reserve(std::size_t n) {
  if (n <= entry.size()) return;
  const std::size_t capacity = n + n / 2;  // grown rarely, so zero-filling is no cost
  entry.resize(capacity);
  separated.resize(capacity);
  branch.resize(capacity);
  dist2.resize(capacity);
}

using pairs::PairInputs;

void ContactForces::GhostPairs::take(const NeighborList& list, const std::vector<std::int32_t>& ghosts,
                                     std::size_t lower) {
  const PairData& pd = list.pairs();
  const std::size_t count = ghosts.size();
  const bool spheroids = !pd.spheroid.empty();
  owner.resize(count);
  entries.resize(count, spheroids);
  for (std::size_t k = 0; k < count; ++k) {
    const auto e = static_cast<std::size_t>(ghosts[k]);
    owner[k] = list.owners()[e];
    entries.partner[k] = pd.partner[e];
    entries.spring[k] = pd.spring[e];
    entries.state[k] = pd.state[e];
    entries.active[k] = pd.active[e];
    if (spheroids) entries.spheroid[k] = pd.spheroid[e];
  }
  off = {0, static_cast<std::int32_t>(lower), static_cast<std::int32_t>(count)};
}

void ContactForces::GhostPairs::point(PairInputs& in) {
  in.off = off.data();
  in.owner = owner.data();
  in.partner = entries.partner.data();
  in.spring = entries.spring.data();
  in.state = entries.state.data();
  in.active = entries.active.data();
  in.sph = entries.spheroid.empty() ? nullptr : entries.spheroid.data();
}

void ContactForces::set_viscous_damping(const ViscousContactDamping& d) { viscous_a_ = d.coefficient(); }

ContactSums ContactForces::compute(const Particles& p, const PeriodicCell& cell, NeighborList& list,
                                   const HertzMindlin& law, double dt, bool measure,
                                   std::vector<Vec3>& force, std::vector<Vec3>& torque) {
  const std::size_t n = p.size();
  const std::int32_t nchunks = chunk_count(n);
  chunk_sums_.assign(static_cast<std::size_t>(nchunks), ContactSums{});
  PairData& pd = list.pairs();
  const bool spheroids = list.has_spheroids();
  if (spheroids && pd.spheroid.size() != pd.size())
    throw std::logic_error("contact forces: neighbour list without spheroid pair states");
  if (spheroids) bodies_.resize(n);
  force.resize(n);
  torque.resize(n);
  // The pair loops sum the particles: one thread all of them, a team's
  // threads their runs' (own_begin, own_span set per thread below); each
  // zeroes the sums it makes.
  PairInputs in{p.frac.data(),     p.velocity.data(),     p.omega.data(),
                    p.radius.data(),   list.offsets().data(), list.owners().data(),
                    pd.partner.data(), pd.spring.data(),      pd.state.data(),
                    pd.active.data(),  bodies_.data(),
                    sleep_ ? motion_clock_ : std::numeric_limits<double>::infinity(), sleep_,
                    p.shape.data(),    pd.spheroid.data(),    cell.h(),
                    cell.velocity_gradient(),                 law,
                    dt,                force.data(),          torque.data(),
                    p.mass.data(),     viscous_a_};
  ContactSums* sums = chunk_sums_.data();
  if (static_cast<int>(scratch_.size()) < omp_get_max_threads())
    scratch_.resize(static_cast<std::size_t>(omp_get_max_threads()));
  Scratch* scratch = scratch_.data();
  phases_.ensure_threads(omp_get_max_threads());
  PhaseTimes* phases = &phases_;

  const double* rad = p.radius.data();
  Vec3* fout = force.data();
  Vec3* tout = torque.data();
  const std::int32_t ni = static_cast<std::int32_t>(n);

  // One thread and a team of several alike (a team's kernels sum no
  // particle outside the thread's run, owner or partner: PairInputs::home;
  // the ghosts run the same kernel, split_sums.h).
  const pairs::PairKernel kernel = spheroids ? pairs::spheroid_pair_kernel(measure, viscous_a_ > 0.0)
                                            : pairs::sphere_pair_kernel(measure, viscous_a_ > 0.0);

  // Support data and contact radii of particles [i0, i1) (PairBody;
  // symmetry axis e = q (1,0,0)): one rotation per particle instead of one
  // per particle and pair.
  const auto refresh_bodies = [&](std::int32_t i0, std::int32_t i1) {
    const Vec3* axes = p.semi_axes.data();
    const Quaternion* orient = p.orientation.data();
    const Shape* shape = p.shape.data();
    PairBody* body = bodies_.data();
    for (std::int32_t i = i0; i < i1; ++i) {
      body[i].support = SpheroidSupport::of(Spheroid::from_semi_axes(axes[i], orient[i]));
      const bool spheroid = shape[i] == Shape::Spheroid;
      body[i].radii = {spheroid ? (axes[i].x + 2.0 * axes[i].y) / 3.0 : rad[i], spheroid ? axes[i].y : rad[i]};
    }
  };
  SplitSums* split = &split_;
  ThreadRuns* runs = &runs_;
  // The plan is checked before the team forms, so that every thread takes
  // the same path (a team smaller than planned remakes it).
  const int planned_team = omp_get_max_threads();
  const bool plan_current = runs_.current(nchunks, n, planned_team) && split_.current(list, n, runs_);
  bool plan_used = false;  // set by a team of several
  // On a team, each thread's ghosts (split_sums.h) follow on from the last
  // compute() only when that was a team's with this plan; else their
  // per-entry state is taken from the list (where the owners keep it)
  // before the pair loops.
  const bool ghosts_follow = ghosts_follow_;
  std::vector<GhostPairs>* ghost_pairs = &ghost_pairs_;
  const double region_start = omp_get_wtime();

  // One parallel region. One thread: the pair loop sums per particle itself,
  // in list order. Several (split_sums.h): each
  // thread's pair loop sums its run's particles, with the pairs owned in
  // other runs whose partner is home evaluated again as ghosts, before
  // and after its chunks.
#pragma omp parallel
  {
    Scratch& mine = scratch[omp_get_thread_num()];
    const int team = omp_get_num_threads();
    const auto evaluate_chunk = [&](const PairInputs& inputs, std::int32_t c) {
      const std::int32_t i_begin = c * kChunkSize;
      const std::int32_t i_end = std::min<std::int32_t>(ni, i_begin + kChunkSize);
      mine.reserve(static_cast<std::size_t>(in.off[i_end] - in.off[i_begin]));
      sums[c] = kernel(inputs, i_begin, i_end, mine.entry.data(), mine.separated.data(), mine.branch.data(),
                       mine.dist2.data());
    };
    if (team == 1) {
      // One thread, chunks in ascending order: the pair loop visits every
      // pair in list order, the order of the per-particle sums.
      const double t0 = omp_get_wtime();
      if (spheroids) refresh_bodies(0, ni);
      std::fill(fout, fout + ni, Vec3{});
      std::fill(tout, tout + ni, Vec3{});
      const double t1 = omp_get_wtime();
      for (std::int32_t c = 0; c < nchunks; ++c) evaluate_chunk(in, c);
      phases->add(0, PhaseTimes::Prepare, t1 - t0);
      phases->add(0, PhaseTimes::Pairs, omp_get_wtime() - t1);
    } else {
      // Several threads: each takes its run of consecutive chunks (the run
      // of the integrator too) for the spheroids' support data, the pairs
      // and the sums, so it mostly reads the particles it wrote itself.
      // The runs are cut by the time of that work (split_sums.h).
      const int t = omp_get_thread_num();
      if (!plan_current || team != planned_team || !ghosts_follow) {
#pragma omp single
        {
          const double planning = omp_get_wtime();
          runs->prepare(nchunks, n, team);
          split->prepare(list, n, *runs);
          ghost_pairs->resize(static_cast<std::size_t>(team));
          phases->add(t, PhaseTimes::Prepare, omp_get_wtime() - planning);
        }
        // (implicit barrier: the plan is ready) each thread's ghosts from
        // the list, by the thread itself (its cache), before any pair loop
        // writes the list
        const double taking = omp_get_wtime();
        (*ghost_pairs)[static_cast<std::size_t>(t)].take(list, split->ghosts(t), split->ghosts_lower(t));
        phases->add(t, PhaseTimes::Prepare, omp_get_wtime() - taking);
#pragma omp barrier
      }
      if (t == 0) plan_used = true;
      const auto [c0, c1] = runs->run(t);
      const double start = omp_get_wtime();
      // home: particles [i0, i1); the pair loop, with the ghosts of the
      // pairs owned in other runs, sums them in the one-thread order
      const std::int32_t i0 = std::min(ni, c0 * kChunkSize), i1 = std::min(ni, c1 * kChunkSize);
      if (spheroids) refresh_bodies(i0, i1);
      std::fill(fout + i0, fout + i1, Vec3{});
      std::fill(tout + i0, tout + i1, Vec3{});
      const double prepared = omp_get_wtime() - start;
      if (spheroids) {
#pragma omp barrier
        // (every run's support data is ready for its partners)
      }
      const double pairs_start = omp_get_wtime();
      PairInputs own = in;
      own.force_out = fout;
      own.torque_out = tout;
      own.own_begin = i0;
      own.own_span = static_cast<std::uint32_t>(i1 - i0);
      // the ghosts owned in lower runs, the run's chunks, the ghosts owned
      // in higher runs: each home particle's terms in list order, so its
      // sums are done when this thread's pair loop is (split_sums.h). A
      // ghost is the pair kernel itself on the thread's copies of the
      // entries (GhostPairs: a list of two "owners", the lower and the
      // higher ghosts), adding to its home partners only; its sums are
      // the owner's to count.
      GhostPairs& mine_ghosts = (*ghost_pairs)[static_cast<std::size_t>(t)];
      PairInputs ghosts = own;
      mine_ghosts.point(ghosts);
      mine.reserve(mine_ghosts.owner.size());
      const auto run_ghosts = [&](std::int32_t part) {
        kernel(ghosts, part, part + 1, mine.entry.data(), mine.separated.data(), mine.branch.data(),
               mine.dist2.data());
      };
      run_ghosts(0);
      for (std::int32_t c = c0; c < c1; ++c) evaluate_chunk(own, c);
      run_ghosts(1);
      const double paired = omp_get_wtime() - pairs_start;
      runs->record(t, prepared + paired);
      phases->add(t, PhaseTimes::Prepare, prepared);
      phases->add(t, PhaseTimes::Pairs, paired);
    }
  }
  phases_.add_region(PhaseTimes::ForceRegion, omp_get_wtime() - region_start);
  split_used_ = plan_used;
  ghosts_follow_ = plan_used;

  ContactSums total;
  for (const ContactSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
