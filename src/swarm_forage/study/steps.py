"""The study's steps: each sweep called in this process (swarm_forage.sweep.cli), the figures, the report and the
ablation's table as processes of their own, and --decide's rounds of more seeds. A step that fails ends the
study with `paper: <step> failed (the same command resumes)`, as before it the step's own message."""
import contextlib
import io
import json
import os
import subprocess
import sys
import time
import traceback

import yaml

from swarm_forage.paths import PACKAGE
from swarm_forage.sweep import cli as sweep_cli
from swarm_forage.sweep import rounds as rr

EXPERIMENTS = os.path.join(PACKAGE, 'config', 'experiments')


def step(what, cmd):
    """Runs one step; returns its wall time [s]."""
    print('paper: %s' % what, flush=True)
    start = time.time()
    if subprocess.run(cmd).returncode != 0:
        sys.exit('paper: %s failed (the same command resumes)' % what)
    return time.time() - start


def python_module(name):
    """The words that run the command of module `name` (swarm_forage.<name>) as a process."""
    return [sys.executable, '-m', 'swarm_forage.' + name]


def call(main, argv):
    """main(argv)'s exit status as a process of it would end: SystemExit's code (None: 0; a message: printed, 1),
    an exception's traceback printed and 1."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    except Exception:  # a process of it would print the traceback and exit 1
        traceback.print_exc()
        code = 1
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
    if code is None or isinstance(code, int):
        return code or 0
    print(code, file=sys.stderr)
    return 1


class Lines(io.TextIOBase):
    """What is written through it goes on to `out` at once and is kept as whole lines."""

    def __init__(self, out):
        super().__init__()
        self.out, self.lines, self.part = out, [], ''

    def write(self, text):
        self.out.write(text)
        self.part += text
        *whole, self.part = self.part.split('\n')
        self.lines += whole
        return len(text)

    def flush(self):
        self.out.flush()


def seeds_file(out, name):
    """OUT/seeds/NAME.tsv: the group-runs file of sweep NAME (the seeds --decide gave its groups)."""
    return os.path.join(out, 'seeds', name + '.tsv')


def decided_note(out, plan):
    """The note's words on the seeds --decide added (OUT/seeds/*.tsv), or ''."""
    seeds = {n: rr.read_group_runs(seeds_file(out, n)) for n, _, _ in plan if os.path.isfile(seeds_file(out, n))}
    return ''.join('; %s: %d groups given more seeds to decide a claim (%s)' % (
        n, len(c), os.path.relpath(seeds_file(out, n), out)) for n, c in seeds.items())


def run_sweep(out, name, experiment_name, args, extra, plan=(), plans=None):
    """sweep NAME into OUT/NAME, with OUT/seeds/NAME.tsv when --decide wrote one, reusing the runs the study's
    other sweep folders hold (--reuse, e.g. ideal_64x32's ideal runs as time_varying_64x32's references);
    returns its wall time. A dry run (`plans`: a folder for the plans) counts instead the runs the sweeps
    before it would make (--planned), and sums every sweep's totals."""
    seeds = seeds_file(out, name)
    argv = [os.path.join(EXPERIMENTS, experiment_name + '.yaml'), '--out', os.path.join(out, name)] + args + extra + \
        (['--group-runs', seeds] if os.path.isfile(seeds) else [])
    others = [n for n, _, _ in plan if n != name]
    argv += [w for n in others if os.path.isfile(os.path.join(out, n, 'runs.tsv'))
             for w in ('--reuse', os.path.join(out, n))]
    what = 'sweep %s' % name
    if plans is None:
        print('paper: %s' % what, flush=True)
        start = time.time()
        if call(sweep_cli.main, argv) != 0:
            sys.exit('paper: %s failed (the same command resumes)' % what)
        return time.time() - start
    argv += [w for n in others if os.path.isfile(os.path.join(plans['dir'], n + '.tsv'))
             for w in ('--planned', os.path.join(plans['dir'], n + '.tsv'))]
    argv += ['--plan-file', os.path.join(plans['dir'], name + '.tsv')]
    print('paper: %s (dry run)' % what, flush=True)
    start = time.time()
    lines = Lines(sys.stdout)
    with contextlib.redirect_stdout(lines):
        code = call(sweep_cli.main, argv)
    plans['totals'] += [dict(w.split('=', 1) for w in line.split()[2:]) for line in lines.lines
                        if line.startswith('sweep: totals: ')]
    if code != 0:
        sys.exit('paper: %s --dry-run failed (exit %d)' % (what, code))
    return time.time() - start


def dry_run_totals(totals):
    """The study's plan in numbers: one table row per sweep and their sum."""
    keys = ('runs', 'reused', 'todo', 'forks', 'robot_ticks', 'seconds', 'bytes', 'possible_forks', 'seconds_forked')
    rows = [[t['name']] + [float(t.get(k, 0)) for k in keys] for t in totals]
    rows.append(['total'] + [sum(r[k + 1] for r in rows) for k in range(len(keys))])
    print('paper: dry run: the study\'s plan (each sweep estimated on this machine as it is now):')
    print('  %-30s %7s %7s %7s %7s %11s %7s %7s' % ('sweep', 'runs', 'reused', 'to do', 'forks', 'robot-ticks',
                                                 'hours', 'GB'))
    for r in rows:
        print('  %-30s %7d %7d %7d %7d %11.3g %7.1f %7.1f' % (r[0], r[1], r[2], r[3], r[4], r[5], r[6] / 3600,
                                                           r[7] / 1e9))
    if rows[-1][8] > rows[-1][4]:
        print('paper: %d runs could fork from shared prefixes, but this build\'s run_experiment cannot (no save_at:=/'
              'resume:=); with them the study would take %.1f h' % (rows[-1][8], rows[-1][9] / 3600))


def partial(a):
    """--report-only draws and reports sweeps that may not have finished, and says so."""
    return ['--partial'] if a.report_only else []


def report_command(a, out, plan, figures):
    """paper_report.py's words for this study (without --note)."""
    report = python_module('study.report') + partial(a)
    output = ['--figures', figures, '--output', os.path.join(out, 'report.md')]
    if a.arm_96:
        return report + ['--ideal'] + [os.path.join(out, n) for n, _, _ in plan] + ['--claims', 'c,d'] + output + \
            ['--title', 'swarm_forage: the 96×48 arm, claims (c) and (d)']
    ideal = [os.path.join(out, n) for n, _, _ in plan if n.startswith('ideal')]
    robustness = [os.path.join(out, n) for n, _, _ in plan if n.startswith('robustness')]
    return report + ['--ideal'] + ideal + ['--time-varying', os.path.join(out, 'time_varying_64x32'),
                                           '--robustness'] + robustness + output


def cap_of(experiment_name, cap):
    """The most seeds --decide gives a group of a sweep of EXPERIMENT: --cap, else the file's runs."""
    if cap:
        return cap
    with open(os.path.join(EXPERIMENTS, experiment_name + '.yaml')) as f:
        return int(yaml.safe_load(f)['runs'])


def decide(a, out, plan, extra, figures):
    """--decide: report (--json), raise the undecided claims' groups (rounds.decide), sweep those
    sweeps again, until no claim is undecided below its cap."""
    folders = {os.path.realpath(os.path.join(out, n)): (n, e, x) for n, e, x in plan}
    caps = {f: cap_of(e, a.cap) for f, (_, e, _) in folders.items()}
    verdicts = os.path.join(out, 'verdicts.json')
    number = 1
    while True:
        step('report, decide round %d' % number, report_command(a, out, plan, figures) + ['--json', verdicts])
        with open(verdicts) as f:
            claims = json.load(f)
        listings = {f: rr.read_groups(f) for f in folders}
        try:
            raises, lines = rr.decide(claims, listings, caps)
        except ValueError as err:
            sys.exit('paper: --decide: %s' % err)
        for line in lines:
            print('paper: ' + line, flush=True)
        if not raises:
            print('paper: decide round %d: %s' % (number, 'every claim decided or not measured' if not lines else
                                                   'the undecided claims\' groups are at their cap'), flush=True)
            return
        os.makedirs(os.path.join(out, 'seeds'), exist_ok=True)
        for folder, counts in sorted(raises.items()):
            name, experiment_name, args = folders[folder]
            path = seeds_file(out, name)
            kept = rr.read_group_runs(path) if os.path.isfile(path) else {}
            kept.update({g: max(n, kept.get(g, 0)) for g, n in counts.items()})
            rr.write_group_runs(path, kept, 'seeds per group of %s, written by paper --decide (round %d)'
                                % (name, number))
            run_sweep(out, name, experiment_name, args, extra, plan)
        number += 1
