#!/usr/bin/env python3
r"""Issue 13's ratios from a kept matrix, by both costs of each run.

    RAW_DIR=DIR REPEATS=5 TILES="3x2x2 5x5x4" THREADS="1 2" \
        SHAPES="sphere spheroid" bench/run_matrix.sh
    bench/matrix_both_costs.py DIR

For each round of the matrix (DIR holds triax_bench's output of every run,
named SIZE_THREADS_SHAPE_ROUND, as run_matrix.sh names them) prints the
rounds' ratios -- two / one thread, x_N1 (the largest tile over the
smallest), spheroid / sphere -- and their median over the
rounds, once with each run's mean cost (us_per_particle_step) and once with
its median step (us_per_particle_step_median_step: the cost outside spells
where the host runs two threads one after the other); then each case's
costs and the two-thread runs' slow windows.
"""
import os
import statistics
import sys


def read_runs(folder):
    runs = {}
    for name in os.listdir(folder):
        parts = name.split('_')
        if name.endswith('.idle') or len(parts) != 4 or not parts[3].isdigit() or not os.path.isfile(os.path.join(folder, name)):
            continue  # not a run's output
        size, threads, shape, rnd = parts
        values = {}
        with open(os.path.join(folder, name)) as f:
            for line in f:
                if ': ' in line:
                    key, value = line.split(': ', 1)
                    values[key] = value.strip()
        runs[(size, threads, shape, int(rnd))] = values
    return runs


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        sys.exit(__doc__)
    runs = read_runs(argv[1])
    rounds = sorted({k[3] for k in runs})
    sizes = sorted({k[0] for k in runs if rounds and (k[0], '1', 'sphere', rounds[0]) in runs},
                   key=lambda s: int(runs[(s, '1', 'sphere', rounds[0])]['particles']))
    if len(sizes) < 2:
        sys.exit(f'matrix_both_costs: {argv[1]} needs runs of two tiles (one thread, spheres, every round)')
    small, large = sizes[0], sizes[-1]
    cases = {
        f'two/one {small} sphere': ((small, '1', 'sphere'), (small, '2', 'sphere')),
        f'two/one {large} sphere': ((large, '1', 'sphere'), (large, '2', 'sphere')),
        f'two/one {small} spheroid': ((small, '1', 'spheroid'), (small, '2', 'spheroid')),
        'x_N1 one sphere': ((large, '1', 'sphere'), (small, '1', 'sphere')),
        'x_N1 two sphere': ((large, '2', 'sphere'), (small, '2', 'sphere')),
        f'spheroid/sphere one {small}': ((small, '1', 'spheroid'), (small, '1', 'sphere')),
        f'spheroid/sphere two {small}': ((small, '2', 'spheroid'), (small, '2', 'sphere')),
    }
    for key in ('us_per_particle_step', 'us_per_particle_step_median_step'):
        def cost(case, r):
            try:
                return float(runs[case + (r,)][key].split()[0])
            except KeyError:
                sys.exit(f'matrix_both_costs: no {key} for {case} round {r} in {argv[1]}')
        print('==', key)
        for name, (a, b) in cases.items():
            ratios = [cost(a, r) / cost(b, r) for r in rounds]
            print(f'  {name:28s} median {statistics.median(ratios):.3f}  rounds ' +
                  ' '.join(f'{x:.3f}' for x in ratios))
        for size in (small, large):
            for threads in ('1', '2'):
                for shape in ('sphere', 'spheroid'):
                    costs = [cost((size, threads, shape), r) for r in rounds]
                    print(f'  cost {size} {threads}T {shape:8s} median {statistics.median(costs):.4f}  ' +
                          ' '.join(f'{x:.4f}' for x in costs))
    print('== slow windows (two threads)')
    for size in (small, large):
        for shape in ('sphere', 'spheroid'):
            print(' ', size, shape,
                  [runs[(size, '2', shape, r)].get('slow_windows', '?').split(' (')[0] for r in rounds])


if __name__ == '__main__':
    main(sys.argv)
