"""vt_qs_sweep: `triax_qs rate-sweep` and `triax_qs damping-sweep` (issue 15).

The sweeps run through vt_sweep (the code of triax_sweep: parallel,
resumable, local or Slurm); the fits are triax_qs's own (`triax_qs
fit-rates` / `fit-damping`, the C++ quasi_static library), called on the
finished runs' summaries. This package only plans the runs, collects them,
and writes the report folder:

    OUT/base_protocol.yaml   the protocol the runs are made from (sample path
                             absolute, the shear stage's rate and, for a
                             damping sweep, the damping model set)
    OUT/sweep/               the vt_sweep folder (sweep.json, runs/, sweep.csv)
    OUT/runs.csv             one row per run: rate, damping, phi_peak, I_mom, ...
    OUT/fit.json             triax_qs's fit of the completed runs
    OUT/result.json          the result line printed last on stdout
    OUT/*.png, q_eps_a.csv   the figures and the q - eps_a curves

`triax_qs rate-sweep ...` execs scripts/triax_qs_sweep, which runs cli.main.
"""
