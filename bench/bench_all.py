#!/usr/bin/env python3
"""`make bench`: every throughput figure of docs/design.md, Performance targets, in one table.

    bench_all.py [--quick] [--ratios] [--noise K] [--out DIR]

Runs, each case in its own process (peak RSS is per process):
  * headless core (bench_core): CRW, DPO and GP-DPO at N = 1, 1,024 (32x16), 16,384 (96x48) and
    65,536 (256x128: the density of 1,024 in 32x16), threads = cores, and CRW at 16,384 on one thread;
    one robot in 96x48 and in 400x200; 1,048,576 CRW robots (1024x512) for 1,000 ticks;
  * the ceiling loop (bench_ceiling) at the same size and threads right after each headless run, so each
    figure has a ratio to it (headless: the median of 3 such pairs; the figure is the best of the 3 runs);
  * the node graph (4 processes, TCPROS, lockstep) and the nodelet graph (one process) at 16,384;
  * a sweep with -j 2 (GNU Parallel, one thread per run) against one single-threaded run;
  * a Python controller in process (bench_python): the numpy CRW against the C++ CRW, headless, at N = 64,
    1,024 (32x16) and 16,384 (96x48), and the interpreter's own cost per tick.
Prints the table and the targets, writes DIR/bench.csv and DIR/bench.png (robot-ticks/s vs N per mode).
--noise K runs K busy processes alongside: a noisy machine that can be made again. The "1-thr %" column is
the share of a case's pool jobs that ran on one thread because other processes wanted the cores.
"""
import argparse
import csv
import os
import re
import statistics
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from bench_graph import run_case  # noqa: E402
from swarm_forage.study.claims import PAPER  # noqa: E402

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.dirname(HERE)
FIELDS = ['mode', 'controller', 'n', 'arena', 'threads', 'ticks', 'robot_ticks_per_s', 'ns_per_robot_tick',
          'peak_rss_mib', 'startup_s', 'ceiling_robot_ticks_per_s', 'ratio_to_ceiling', 'jobs_on_one_thread_pct']
ONE_THREAD = re.compile(r'([\d.]+) % of jobs on one thread')


def tool(name):
    out = subprocess.run(['catkin_find', 'swarm_forage', name], stdout=subprocess.PIPE, text=True).stdout.split()
    if not out:
        sys.exit('bench_all: %s is not built (make build)' % name)
    return out[0]


def progress(message):
    print('... ' + message, file=sys.stderr, flush=True)


def core(rows, controller, n, arena, ticks, threads=0, repeats=3):
    """`repeats` runs, each followed at once by the ceiling loop at the same size and thread count: the
    case's figure is its best run (a shared machine's neighbours only ever slow a run down), its ratio the
    median of the pairs' ratios, so a slow second that hits one side of one pair does not decide it."""
    progress('headless %s N=%d %s threads=%s (%d runs, each with the ceiling loop)'
             % (controller, n, arena, threads or 'cores', repeats))
    best, ratios, ceilings = None, [], []
    for _ in range(repeats):
        with tempfile.NamedTemporaryFile('r', suffix='.csv') as f:
            out = subprocess.run([tool('bench_core'), '--controller', controller, '--n', str(n), '--arena', arena,
                                  '--ticks', str(ticks), '--threads', str(threads), '--csv', f.name], check=True,
                                 stdout=subprocess.PIPE, text=True).stdout
            row = dict(zip(FIELDS, f.read().strip().split(',')[:10]))
        row['jobs_on_one_thread_pct'] = ONE_THREAD.search(out).group(1)
        ceilings.append(run_ceiling(n, arena, int(row['threads']), ceiling_ticks(n, ticks)))
        ratios.append(float(row['robot_ticks_per_s']) / ceilings[-1])
        if best is None or float(row['robot_ticks_per_s']) > float(best['robot_ticks_per_s']):
            best = row
    best['ceiling_robot_ticks_per_s'] = '%.4g' % statistics.median(ceilings)
    best['ratio_to_ceiling'] = '%.3f' % statistics.median(ratios)
    CEILINGS.setdefault((n, arena, int(best['threads'])), statistics.median(ceilings))
    rows.append(best)
    return best


def busy_processes(k):
    """K processes that only spin, as a busy neighbour does; the caller ends them (by pid)."""
    return [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(k)]


def ceiling_ticks(n, ticks):
    return 20000 if n == 1 else ticks


CEILINGS = {}


def run_ceiling(n, arena, threads, ticks):
    out = subprocess.run([tool('bench_ceiling'), '--n', str(n), '--arena', arena, '--ticks', str(ticks),
                          '--threads', str(threads)], check=True, stdout=subprocess.PIPE, text=True).stdout
    return float(re.search(r': ([\d.e+]+) robot-ticks/s', out).group(1))


def ceiling(n, arena, threads, ticks):
    """The ceiling loop at this size and thread count: the headless cases' median, else one run."""
    key = (n, arena, threads)
    if key not in CEILINGS:
        progress('ceiling N=%d %s threads=%d' % (n, arena, threads))
        CEILINGS[key] = run_ceiling(n, arena, threads, ticks)
    return CEILINGS[key]


def graph(rows, mode, controller, n, arena, ticks):
    progress('%s graph %s N=%d %s (best of 2)' % (mode, controller, n, arena))
    rate = max(run_case(controller, n, arena, ticks, nodelet=mode == 'nodelet')[3] for _ in range(2))
    rows.append({'mode': mode, 'controller': controller, 'n': n, 'arena': arena, 'threads': os.cpu_count(),
                 'ticks': ticks, 'robot_ticks_per_s': rate, 'ns_per_robot_tick': 1e9 / rate,
                 'peak_rss_mib': '', 'startup_s': ''})


def sweep_pair(rows, ticks):
    """Aggregate robot-ticks/s of a -j 2 sweep (GNU Parallel's joblog) against one single-threaded run."""
    n, arena = 4096, '64x32'
    progress('one single-threaded run, then a sweep of 4 runs with -j 2 (CRW N=%d %s)' % (n, arena))
    folder = tempfile.mkdtemp(prefix='swarm_forage_bench_sweep_')
    try:
        start = time.time()
        subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'controller:=crw', 'n_robots:=%d' % n,
                        'arena:=' + arena, 'ticks:=%d' % ticks, 'threads:=1'], check=True, stdout=subprocess.DEVNULL)
        single = n * ticks / (time.time() - start)
        exp = os.path.join(folder, 'exp.yaml')
        with open(exp, 'w') as f:
            f.write('name: bench_j2\narena: %s\ncontrollers: [crw]\nsizes: {min: %d, max: %d}\nruns: 4\n'
                    'ticks: %d\nsample_interval: %d\nconditions:\n  - {waveform: "null"}\n'
                    % (arena, n, n, ticks, max(1, ticks // 4)))
        out = os.path.join(folder, 'out')
        subprocess.run([os.path.join(ROOT, 'scripts', 'sweep'), exp, '--out', out, '-j', '2'], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(os.path.join(out, 'joblog.txt')) as f:
            jobs = [line.split('\t') for line in f.read().splitlines()[1:] if line.strip()]
        first = min(float(j[2]) for j in jobs)
        last = max(float(j[2]) + float(j[3]) for j in jobs)
        both = len(jobs) * n * ticks / (last - first)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    for mode, rate, threads in (('single_run_1_thread', single, 1), ('sweep_j2', both, 2)):
        rows.append({'mode': mode, 'controller': 'crw', 'n': n, 'arena': arena, 'threads': threads, 'ticks': ticks,
                     'robot_ticks_per_s': rate, 'ns_per_robot_tick': 1e9 / rate, 'peak_rss_mib': '', 'startup_s': ''})
    return both / single


def python_pair(rows, ticks):
    """bench_python: the numpy CRW and the C++ CRW headless at each of its sizes; {N: numpy / C++}."""
    progress('headless numpy CRW (in process) against the C++ CRW, N = 64, 1,024, 16,384')
    out = subprocess.run([tool('bench_python'), '--ticks', str(ticks)], check=True, stdout=subprocess.PIPE,
                         text=True).stdout
    print(out, end='')
    ratios = {}
    for line in out.splitlines()[1:]:
        n, arena, cpp, numpy, ratio, _, numpy_us, idle_us = line.split()
        ratios[int(n)] = float(ratio)
        for controller, rate in (('crw', cpp), ('numpy_crw', numpy)):
            rows.append({'mode': 'python' if controller == 'numpy_crw' else 'headless (bench_python)',
                         'controller': controller, 'n': n, 'arena': arena, 'threads': str(os.cpu_count()),
                         'ticks': str(ticks), 'robot_ticks_per_s': rate,
                         'ns_per_robot_tick': '%.4g' % (1e9 / float(rate))})
        print('  N=%s: the interpreter alone %s us a tick, the numpy CRW\'s control %s us' % (n, idle_us, numpy_us))
    return ratios


def plot(rows, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 5))
    series = {}
    for r in rows:
        if r['mode'] in ('headless', 'graph', 'nodelet', 'python') and int(r['n']) > 1:
            label = '%s %s (%s threads)' % (r['mode'], r['controller'], r['threads'])
            series.setdefault(label, []).append((int(r['n']), float(r['robot_ticks_per_s'])))
    for label, pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], 'o-', label=label)
    ceil = sorted((k[0], v) for k, v in CEILINGS.items() if k[0] > 1 and k[2] == os.cpu_count())
    if ceil:
        ax.plot([c[0] for c in ceil], [c[1] for c in ceil], 'k--', label='ceiling loop (cores)')
    ax.axhline(2e7, color='grey', lw=0.8, ls=':')
    ax.text(1100, 2.1e7, 'CRW target 2e7', color='grey', fontsize=8)
    ax.set_xscale('log', base=2)
    ax.set_yscale('log')
    ax.set_xlabel('robots N')
    ax.set_ylabel('robot-ticks per second')
    ax.set_title('swarm_forage throughput (%d cores)' % os.cpu_count())
    ax.grid(True, which='both', alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def report_checks(checks):
    print('\ntargets (docs/design.md, Performance targets, with the ratios):')
    for name, value, op, target in checks:
        ok = value >= target if op == '>=' else value <= target
        print('  %-58s %10.3g  target %s %-8.3g %s' % (name, value, op, target, 'met' if ok else 'NOT MET'))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  make bench BENCH_ARGS=--quick   # bench_all.py --quick')
    ap.add_argument('--quick', action='store_true', help='fewer ticks; no 1,048,576-robot run')
    ap.add_argument('--ratios', action='store_true',
                    help='only the headless N = 16,384 cases (CRW, DPO, GP-DPO on the cores, CRW on one thread) '
                         'and their ratio to the ceiling (a few minutes)')
    ap.add_argument('--noise', type=int, default=0, metavar='K',
                    help='K busy processes alongside every case: a noisy machine (default: 0)')
    ap.add_argument('--out', default=os.path.join(ROOT, 'results', 'bench'), help='(default: %(default)s)')
    a = ap.parse_args()
    if not 0 <= a.noise <= 64:
        ap.error('--noise must be 0 to 64 busy processes (got %d)' % a.noise)
    busy = busy_processes(a.noise)
    try:
        measure(a)
    finally:
        for p in busy:
            p.kill()
            p.wait()


def measure(a):
    os.makedirs(a.out, exist_ok=True)
    ticks = 300 if a.quick else 1000
    rows = []
    sizes = [(16384, '96x48')] if a.ratios else [(1024, '32x16'), (16384, '96x48'), (65536, '256x128')]
    for controller in PAPER:
        for n, arena in sizes:
            core(rows, controller, n, arena, ticks if n < 65536 else max(100, ticks // 4))
    core(rows, 'crw', 16384, '96x48', ticks, threads=1)
    if not a.ratios:
        lone = [core(rows, 'crw', 1, arena, 20000 if a.quick else 100000) for arena in ('96x48', '400x200')]
        if not a.quick:
            big = core(rows, 'crw', 1048576, '1024x512', 1000, repeats=1)
        for mode in ('graph', 'nodelet'):
            for controller in PAPER:
                graph(rows, mode, controller, 16384, '96x48', ticks)
        j2 = sweep_pair(rows, ticks * 3)
        python = python_pair(rows, ticks)
    for r in rows:  # every other case against the ceiling loop at its size and thread count
        if 'ratio_to_ceiling' in r:
            continue
        n = int(r['n'])
        c = ceiling(n, r['arena'], int(r['threads']), ceiling_ticks(n, int(r['ticks'])))
        r['ceiling_robot_ticks_per_s'] = '%.4g' % c
        r['ratio_to_ceiling'] = '%.3f' % (float(r['robot_ticks_per_s']) / c)

    with open(os.path.join(a.out, 'bench.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction='ignore')
        w.writeheader()
        for r in rows:
            w.writerow(r)
    plot(rows, os.path.join(a.out, 'bench.png'))

    print('%-20s %-7s %8s %-9s %3s %12s %9s %9s %9s %7s %8s' % (
        'mode', 'ctrl', 'N', 'arena', 'thr', 'robot-ticks/s', 'ns/r-tick', 'RSS MiB', 'startup s', 'x ceil', '1-thr %'))
    for r in rows:
        print('%-20s %-7s %8s %-9s %3s %12.3g %9.1f %9s %9s %7s %8s' % (
            r['mode'], r['controller'], r['n'], r['arena'], r['threads'], float(r['robot_ticks_per_s']),
            float(r['ns_per_robot_tick']), r.get('peak_rss_mib', ''), r.get('startup_s', ''),
            r.get('ratio_to_ceiling', ''), r.get('jobs_on_one_thread_pct', '')))

    def rate(mode, controller, n, threads=None):
        for r in rows:
            if r['mode'] == mode and r['controller'] == controller and int(r['n']) == n and \
                    (threads is None or int(r['threads']) == threads):
                return float(r['robot_ticks_per_s'])
        return float('nan')

    def ratio(controller, threads):
        for r in rows:
            if r['mode'] == 'headless' and r['controller'] == controller and int(r['n']) == 16384 and \
                    int(r['threads']) == threads:
                return float(r['ratio_to_ceiling'])
        return float('nan')

    cores = os.cpu_count()
    at_least, at_most = '>=', '<='
    checks = [('headless CRW N=16384, robot-ticks/s', rate('headless', 'crw', 16384, cores), at_least, 2e7)]
    for c in ('dpo', 'gp_dpo'):
        checks.append(('headless %s N=16384, robot-ticks/s' % c, rate('headless', c, 16384, cores), at_least, 1e7))
    # The per-core targets, as ratios to the ceiling loop of the same run (they carry across machines).
    checks.append(('headless CRW N=16384 / ceiling, %d threads' % cores, ratio('crw', cores), at_least, 0.75))
    checks.append(('headless CRW N=16384 / ceiling, 1 thread', ratio('crw', 1), at_least, 0.75))
    for c in ('dpo', 'gp_dpo'):
        checks.append(('headless %s N=16384 / ceiling, %d threads' % (c, cores), ratio(c, cores), at_least, 0.45))
    if a.ratios:
        report_checks(checks)
        return
    for c in PAPER:
        checks.append(('node graph %s N=16384, robot-ticks/s' % c, rate('graph', c, 16384), at_least, 5e6))
        checks.append(('nodelet graph %s N=16384 / headless' % c,
                       rate('nodelet', c, 16384) / rate('headless', c, 16384, cores), at_least, 0.7))
        checks.append(('%s ns per robot-tick, N=65536 / N=1024 (same density)' % c,
                       rate('headless', c, 1024, cores) / rate('headless', c, 65536, cores), at_most, 1.5))
    checks.append(('one robot in 96x48, ticks/s', float(lone[0]['robot_ticks_per_s']), at_least, 1e5))
    checks.append(('one robot: ns per tick, 400x200 / 96x48 (flat)',
                   float(lone[0]['robot_ticks_per_s']) / float(lone[1]['robot_ticks_per_s']), at_most, 1.25))
    checks.append(('sweep -j 2 / one single-threaded run, robot-ticks/s', j2, at_least, 1.8))
    checks.append(('numpy CRW / C++ CRW in process, N=16384 (96x48)', python.get(16384, float('nan')), at_least, 0.3))
    if not a.quick:
        checks.append(('1,048,576 robots: start-up, s', float(big['startup_s']), at_most, 2.0))
    report_checks(checks)
    if not a.quick:
        print('  1,048,576 robots x 1,000 ticks: %.3g robot-ticks/s, start-up %s s, peak RSS %s MiB' % (
            float(big['robot_ticks_per_s']), big['startup_s'], big['peak_rss_mib']))
    print('\nwrote %s and %s' % (os.path.join(a.out, 'bench.csv'), os.path.join(a.out, 'bench.png')))


if __name__ == '__main__':
    main()
