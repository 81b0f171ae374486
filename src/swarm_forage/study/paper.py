"""The paper's study end to end: sweeps, the arena snapshot, figures and the claim-by-claim report.

--quick (`make paper-quick`): every experiment reduced (fewer seeds, smaller maximum N, the time-varying
study at three sizes, the robustness studies at N = 16 and 64); the time it took is printed at the end, and
`--dry-run` estimates it for this machine as it is now. Without --quick (`make paper`): the paper's full study,
50 runs per group up to 16,384 robots (docs/study.md, The full study). Both resume: run the same command
again after a stop. -j, --slurm, --chunk, --partition, --sshlogin and --slf go to every sweep.
--model NAME (and --quirks a,b): every run under that model (`make paper-quick MODEL=fordyca_2019`), into a
folder of its own (results/paper_quick_fordyca_2019), so that the models' records never mix.
--ablation (`make ablation`): the ablation of FORDYCA 2019's quirks instead (docs/FIDELITY.md, "The ablation:
which quirks matter"): the experiment files config/experiments/ablation_*.yaml, each with the model as a sweep
axis, into results/ablation/<file>, then their table (swarm_forage.study.ablation, scripts/ablation_table.py) in
results/ablation/table.md and runs.csv; `--dry-run` estimates it, the same command resumes it.
--reuse DIR (repeatable) goes to every sweep: a planned run that DIR holds complete is linked, not rerun (e.g.
paper-96's records of the ablation's swarm_forage rows).
--decide: then rounds until every claim is decided or its groups have the cap (--cap, else each experiment
file's runs, 50 in the paper's): after each round's sweeps the report's verdicts (paper_report.py --json)
name the undecided claims and the seeds that would decide them, and those groups go to that many seeds
(at least one more, at most the cap; swarm_forage.sweep.rounds.decide) in OUT/seeds/<sweep>.tsv, which
every later `paper` into OUT passes on (sweep --group-runs): the seeds a decision took are kept."""
import argparse
import os
import shutil
import sys
import tempfile
import time

from swarm_forage.experiment import ExperimentError, models
from swarm_forage.paths import PACKAGE
from swarm_forage.study import ablation
from swarm_forage.study.publish import publish, recommend_section
from swarm_forage.study.steps import (decide, decided_note, dry_run_totals, partial, python_module, report_command,
                                      run_sweep, step)
from swarm_forage.sweep import estimate as est

# Said in every report's note: what an invocation made and what it found made.
REUSED = 'runs recorded by an earlier invocation are reused, not redone'

# Robustness (beyond the paper): quick = N 16 and 64, 3 seeds (the fewest that give a spread to
# decide by), 10,000 ticks, 4 of the 9 noise levels and the x1 and x8 rates (docs/robustness-study.md).
ROBUSTNESS_QUICK = ['--runs', '3', '--sizes', '16,64', '--ticks', '10000']
# time_varying_64x32 reuses ideal_64x32's CRW and DPO runs as references: kept checkpoints at alpha (T/2) let
# it fork all their step_up runs instead of running one of each family from tick 0 (sweep --save-prefix).
KEEP_PREFIXES = ['--save-prefix', 'half']
QUICK = [('ideal_32x16', ['--runs', '3']),
         ('ideal_64x32', ['--runs', '3', '--max-size', '2048'] + KEEP_PREFIXES),
         ('time_varying_64x32', ['--runs', '3', '--sizes', '16,64,256']),
         ('robustness_saa_32x16', ROBUSTNESS_QUICK + ['--noise-levels', '0,0.0075,0.015,0.03']),
         ('robustness_pd_32x16', ROBUSTNESS_QUICK + ['--multipliers', '1,8'])]
# The 96x48 arm (make paper-96): claims (c) and (d) where they are made, N = 2,048 ... 16,384 (CRW, DPO;
# GP-DPO at 16,384), 10 seeds, T = 10,000 s; (folder, experiment file, sweep arguments).
ARM_96 = [('ideal_96x48', 'ideal_96x48', ['--controllers', 'crw,dpo', '--sizes', '2048,4096,8192,16384',
                                          '--runs', '10']),
          ('ideal_96x48_gp_dpo', 'ideal_96x48', ['--controllers', 'gp_dpo', '--sizes', '16384', '--runs', '10'])]
# The ablation (make ablation): one sweep per arm, the model an axis of each (ablation_*.yaml).
ABLATION = [(n, n, []) for n in ablation.ARMS]
FULL = [('ideal_32x16', []), ('ideal_64x32', KEEP_PREFIXES), ('ideal_96x48', []), ('time_varying_64x32', []),
        ('robustness_saa_32x16', []), ('robustness_saa_sensors_32x16', []), ('robustness_saa_actuators_32x16', []),
        ('robustness_pd_32x16', [])]
EXAMPLES = """examples:
  rosrun swarm_forage paper --quick                 # results/paper_quick/report.md
  rosrun swarm_forage paper --quick --model fordyca_2019   # results/paper_quick_fordyca_2019/report.md
  rosrun swarm_forage paper --quick --dry-run       # each sweep's plan and estimate; runs and writes nothing
  rosrun swarm_forage paper --slurm --chunk 20      # the full study as SLURM job arrays
  rosrun swarm_forage paper --quick --decide        # then more seeds where a verdict is undecided
  rosrun swarm_forage paper --ablation --dry-run    # the ablation's plan and estimate (make ablation DRY_RUN=1)"""


def parse(argv):
    p = argparse.ArgumentParser(prog='paper', description=__doc__, epilog=EXAMPLES,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--quick', action='store_true', help='the reduced study (make paper-quick)')
    p.add_argument('--arm-96', action='store_true', help='the 96x48 arm only: claims (c) and (d), N = 2,048 ... '
                   '16,384, 10 seeds (make paper-96; results/paper_96)')
    p.add_argument('--ablation', action='store_true', help='the ablation of FORDYCA 2019\'s quirks (make ablation; '
                   'results/ablation): its sweeps, then its table')
    p.add_argument('--out', help='output folder (default: PACKAGE/results/paper_quick or PACKAGE/results/paper, '
                   'with _<model>[_<quirks>] for a model other than the default; PACKAGE/results/ablation)')
    p.add_argument('--reuse', action='append', default=[], metavar='DIR',
                   help='sweep --reuse DIR for every sweep (repeatable): its complete records of planned runs are '
                   'linked, not rerun')
    p.add_argument('--model', help='the model of every run: fordyca_2019 (the default: FORDYCA '
                   '2019\'s code as it ran) or swarm_forage (its corrections, docs/FIDELITY.md)')
    p.add_argument('--quirks', help='comma-separated quirks added on top of the model')
    p.add_argument('--dry-run', action='store_true', help='every sweep\'s plan and estimate (sweep --dry-run); '
                   'no run, snapshot, figure or report')
    p.add_argument('--report-only', action='store_true', help='no sweep: the figures and report of the sweeps '
                   'that have tables (a study stopped part way; the same command without it resumes)')
    p.add_argument('--publish', metavar='DIR', help='then copy the report, verdicts, figures and every sweep\'s '
                   'tables into DIR (docs/paper_96, docs/paper_quick): what is committed, and what `recommend '
                   'TARGET DIR` reads; with --ablation its table.md and runs.csv (docs/ablation)')
    p.add_argument('--decide', action='store_true', help='rounds of more seeds until every claim is decided or its '
                   'groups have the cap')
    p.add_argument('--cap', type=int, help='--decide: most seeds per group (default: each experiment file\'s runs)')
    p.add_argument('-j', '--jobs', type=int, help='sweep -j: runs at a time (default: the cores)')
    p.add_argument('--slurm', action='store_true', help='sweep --slurm: each sweep as a SLURM job array')
    p.add_argument('--chunk', type=int, help='sweep --chunk: runs per array task')
    p.add_argument('--partition', help='sweep --partition')
    p.add_argument('--sshlogin', action='append', default=[], help='sweep --sshlogin (repeatable)')
    p.add_argument('--slf', help='sweep --slf')
    p.add_argument('--compression', choices=est.COMPRESSIONS,
                   help='sweep --compression: the records\' (default bz2; lz4: less time, more disk)')
    a = p.parse_args(argv)
    for name in ('jobs', 'chunk', 'cap'):
        if getattr(a, name) is not None and getattr(a, name) < 1:
            p.error('--%s must be >= 1 (got %d)' % ('j' if name == 'jobs' else name, getattr(a, name)))
    if a.publish and a.dry_run:
        p.error('--dry-run writes nothing: it goes without --publish')
    if a.report_only and (a.decide or a.dry_run):
        p.error('--report-only runs no sweep: it goes with neither --decide nor --dry-run')
    if a.ablation and (a.quick or a.arm_96 or a.decide or a.model or a.quirks):
        p.error('--ablation goes without --quick, --arm-96, --decide, --model and --quirks: its experiment files '
                'name the model of every row (their models axis)')
    for folder in a.reuse:
        if not os.path.isfile(os.path.join(folder, 'runs.tsv')):
            p.error('--reuse %s is not a sweep folder (it has no runs.tsv)' % folder)
    extra = (['-j', str(a.jobs)] if a.jobs else []) + (['--slurm'] if a.slurm else []) + \
        (['--chunk', str(a.chunk)] if a.chunk else []) + (['--partition', a.partition] if a.partition else []) + \
        [w for login in a.sshlogin for w in ('--sshlogin', login)] + (['--slf', a.slf] if a.slf else []) + \
        (['--dry-run'] if a.dry_run else []) + (['--model', a.model] if a.model else []) + \
        (['--quirks', a.quirks] if a.quirks else []) + (['--compression', a.compression] if a.compression else []) + \
        [w for folder in a.reuse for w in ('--reuse', os.path.abspath(folder))]
    try:
        a.model, a.quirks = models.model_choice(a.model, a.quirks, '--model', '--quirks')
    except ExperimentError as err:
        p.error(str(err))
    return a, extra


def arm_96_report(a, out, plan, start):
    """The 96x48 arm's figures and report (claims c and d)."""
    folders = [os.path.join(out, n) for n, _, _ in plan]
    figures = os.path.join(out, 'figures')
    step('figures', python_module('figures.sweep') + folders + ['--output', figures] + partial(a))
    note = ('The 96×48 arm (`make paper-96`%s): %s%s; %s.' % (
                ', report only, from the records so far' if a.report_only else '',
                '; '.join('%s %s' % (n, ' '.join(x)) for n, _, x in plan), decided_note(out, plan), REUSED))
    step('report', report_command(a, out, plan, figures) + ['--note', note, '--json', os.path.join(out, 'verdicts.json')])
    recommend_section(out)
    if a.publish:
        publish(out, plan, a.publish, True)
    print('paper: done in %.1f min: %s' % ((time.time() - start) / 60, os.path.join(out, 'report.md')))
    return 0


def ablation_table(a, out, plan, start):
    """The ablation's table (ablation_table.py) of its sweeps: OUT/table.md and OUT/runs.csv."""
    folders = [os.path.join(out, n) for n, _, _ in plan]
    note = ('Made by `paper --ablation`%s: %s; %s.' % (
                ' --report-only, from the records so far' if a.report_only else '', ', '.join(n for n, _, _ in plan),
                REUSED))
    step('table', python_module('study.ablation_table') + folders +
         ['--output', os.path.join(out, 'table.md'), '--csv', os.path.join(out, 'runs.csv'), '--note', note] +
         partial(a))
    if a.publish:  # docs/ablation: the table and its runs, one line each
        dest = os.path.abspath(a.publish)
        if os.path.realpath(dest) == os.path.realpath(out):
            sys.exit('paper: --publish %s: that is the ablation\'s own folder; give another (docs/ablation)' % dest)
        os.makedirs(dest, exist_ok=True)
        for name in ('table.md', 'runs.csv'):
            shutil.copyfile(os.path.join(out, name), os.path.join(dest, name))
        print('paper: published %s and %s in %s' % ('table.md', 'runs.csv', dest))
    print('paper: done in %.1f min: %s' % ((time.time() - start) / 60, os.path.join(out, 'table.md')))
    return 0


def main(argv=None):
    a, extra = parse(argv)
    label = models.model_label(a.model, a.quirks)
    kind = 'ablation' if a.ablation else 'paper_96' if a.arm_96 else 'paper_quick' if a.quick else 'paper'
    out = os.path.abspath(a.out or os.path.join(PACKAGE, 'results', kind + ('_' + label if label else '')))
    start = time.time()
    plan = ABLATION if a.ablation else ARM_96 if a.arm_96 else [(n, n, x) for n, x in (QUICK if a.quick else FULL)]
    robustness_time = 0.0
    if a.report_only:  # a study stopped part way: figures and report of the sweeps that have tables
        plan = [p for p in plan if os.path.isfile(os.path.join(out, p[0], 'tables', 'series.csv'))]
        if not plan:
            sys.exit('paper: --report-only: no sweep of this study has tables in %s yet' % out)
        print('paper: --report-only: %s' % ', '.join(n for n, _, _ in plan))
    plans = {'dir': tempfile.mkdtemp(prefix='paper_plans_'), 'totals': []} if a.dry_run else None
    try:
        for name, experiment_name, args in [] if a.report_only else plan:
            took = run_sweep(out, name, experiment_name, args, extra, plan, plans)
            robustness_time += took if name.startswith('robustness') else 0.0
    finally:
        if plans:
            for f in os.listdir(plans['dir']):
                os.remove(os.path.join(plans['dir'], f))
            os.rmdir(plans['dir'])
    if a.dry_run:
        dry_run_totals(plans['totals'])
        print('paper: dry run: then %s%s and %s' % (
            'rounds of more seeds for undecided claims (--decide), ' if a.decide else '',
            'the figures' if a.arm_96 else 'its table:' if a.ablation else 'one GP-DPO snapshot run, the figures',
            os.path.join(out, 'table.md' if a.ablation else 'report.md')))
        return 0
    if a.ablation:
        return ablation_table(a, out, plan, start)
    figures = os.path.join(out, 'figures')
    if a.decide:
        decide(a, out, plan, extra, figures)
    if a.arm_96:
        return arm_96_report(a, out, plan, start)
    snapshot = os.path.join(out, 'snapshot_gp_dpo_32x16_n256.bag')
    if not os.path.exists(snapshot):  # the paper's Figure 1: a GP-DPO swarm with its cache, mid-run
        step('arena snapshot run', ['rosrun', 'swarm_forage', 'run_experiment', 'controller:=gp_dpo', 'n_robots:=256',
                                    'seed:=1', 'ticks:=15001', 'record_every:=15000', 'bag:=' + snapshot] +
             ['%s:=%s' % kv for kv in models.model_words(a.model, a.quirks)])
    step('figures', python_module('figures.sweep') + [os.path.join(out, n) for n, _, _ in plan] +
         ['--output', figures, '--snapshot', snapshot] + partial(a))
    note = ('%s study: %s%s; %s.' % (
                'Reduced (paper-quick)' if a.quick else 'Full',
                '; '.join('%s %s' % (n, ' '.join(x) or '(as in its file)') for n, _, x in plan), decided_note(out, plan),
                REUSED))
    step('report', report_command(a, out, plan, figures) + ['--note', note, '--json',
                                                             os.path.join(out, 'verdicts.json')])
    if a.publish:
        publish(out, plan, a.publish, False)
    print('paper: done in %.1f min, the robustness sweeps %.1f min of it (%d cores, load average %.1f): %s' % (
        (time.time() - start) / 60, robustness_time / 60, os.cpu_count() or 1, os.getloadavg()[0],
        os.path.join(out, 'report.md')))
    return 0

