"""Runs an experiment file's sweep, resumably, and aggregates it.

Each run is one `run_experiment` (headless, no master), or with --graph one node graph with a private
master (`forage`), recorded to
OUT/runs/<controller>_<arena>_n<N>_<condition>[_<noise>][_<pd>][_<model>]_seed<S>_<identity>.bag (bz2, one
snapshot at tick 0; the name the core gives, `run_experiment --identity`) with `label:=` its key. The
identity covers everything that changes the run, files by content, so an edited experiment, arena or series
never reuses an old record; a run whose inputs changed after the plan refuses to start (expect_identity:=),
and the sweep stops saying so.

One sweep per folder: a sweep locks OUT (OUT/sweep.lock names it) for its whole life; a second one
exits 3 naming the holder, and the lock of a killed sweep is taken over with a message. A record
counts only if it is whole: its bag opens and is indexed, ends with a complete world/run_end, and
holds the planned controller, N, seed, ticks and identity, its key as world/provenance label and this code's
model version; anything else is moved to OUT/runs/rejected/ with a .reason file and redone. The tables
(run_tables into OUT/tables) are made from the planned records only (OUT/plan/ links to them); records
of other plans stay in OUT/runs, counted but left out. Ctrl-C, SIGTERM or SIGHUP (unless ignored) stops
the runs in flight (their records are marked incomplete); the same command again resumes.

--precision P runs seeds in rounds: round 1 gives every group --start-runs seeds (default min(cap, 3); the
cap is --runs or the file's runs); after each round's tables, every group whose 95 % interval of final P
(the bootstrap over seeds the report uses, OUT/tables/bootstrap.csv) reaches further than P x its mean
from it gets the seeds a normal approximation asks for (at least one more, at most
the cap), until every group is precise or capped (swarm_forage.sweep.rounds; OUT/precision.tsv keeps the
counts the last round chose, so the same command resumes the round it stopped in). --group-runs FILE
gives groups their own seed counts (GROUP<TAB>RUNS lines; OUT/groups.tsv names the groups).

exit status: 0 every planned record verified and run_tables read them all; 1 a run failed, a record
was rejected at the end, or run_tables could not read or combine a record (all shown; its notes on
metrics the plan cannot give, e.g. no smaller N for e, are shown but do not fail); 2 bad input; 3 OUT
is held by another sweep; 130 interrupted (143 terminated during the preparation)."""
import argparse
import errno
import os
import shlex
import signal
import sys
import tempfile

from swarm_forage.experiment import ExperimentError
from swarm_forage.experiment import file as experiment_file
from swarm_forage.experiment.plan import expand
from swarm_forage.paths import PACKAGE
from swarm_forage.sweep import estimate as est
from swarm_forage.sweep import forks, jobs, slurm
from swarm_forage.sweep import records as rec
from swarm_forage.sweep import rounds as rr
from swarm_forage.sweep.steps import PROG, Session, fail, sweep

EXAMPLES = """examples:
  rosrun swarm_forage sweep config/experiments/ideal_32x16.yaml --runs 2 --max-size 64   # Ctrl-C, then again: resumes
  rosrun swarm_forage sweep config/experiments/ideal_32x16.yaml --dry-run    # the plan and estimate; writes nothing
  rosrun swarm_forage sweep my.yaml --out /shared/sweep --slurm --chunk 20   # a SLURM job array
  rosrun swarm_forage sweep config/experiments/robustness_saa_32x16.yaml --noise-levels 0,0.015,0.03 --runs 2
  rosrun swarm_forage sweep config/experiments/ideal_32x16.yaml --precision 0.05 --runs 20   # rounds: 3 seeds, then more
  rosrun swarm_forage sweep config/experiments/ablation_crw_96x48.yaml --models swarm_forage,fordyca_2019 --dry-run"""


def options():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, epilog=EXAMPLES,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('file', help='experiment file (config/experiments/*.yaml)')
    p.add_argument('--runs', type=int, help='runs per group (seeds 1 ... K) instead of the file\'s')
    p.add_argument('--max-size', type=int, help='largest swarm size to run (refused when below every size)')
    p.add_argument('--sizes', help='comma-separated swarm sizes instead of the file\'s, each once')
    p.add_argument('--ticks', type=int, help='ticks per run instead of the file\'s')
    p.add_argument('--controllers', help='comma-separated subset of the file\'s controllers')
    p.add_argument('--noise-levels', help='comma-separated noise levels instead of the lists of the file\'s noise '
                   'settings')
    p.add_argument('--multipliers', help='comma-separated rate multipliers instead of the lists of the file\'s '
                   'population settings')
    p.add_argument('--model', help='the model every run uses instead of the file\'s: fordyca_2019 (the default) or '
                   'swarm_forage (its corrections; `run_experiment --models` lists them)')
    p.add_argument('--quirks', help='comma-separated quirks added on top of the model, instead of the file\'s')
    p.add_argument('--models', help='the model as an axis, instead of the file\'s model, quirks or models: '
                   'comma-separated settings MODEL[+QUIRK ...] or MODEL+each (one setting per quirk the model '
                   'lacks), e.g. swarm_forage,fordyca_2019,swarm_forage+each')
    p.add_argument('--out', help='output folder (default: PACKAGE/results/sweeps/<name>)')
    p.add_argument('-j', '--jobs', type=int, default=os.cpu_count() or 1,
                   help='runs at a time (default: the cores, %(default)s)')
    p.add_argument('--sshlogin', action='append', default=[], help='GNU Parallel --sshlogin (repeatable)')
    p.add_argument('--slf', help='GNU Parallel --sshloginfile')
    p.add_argument('--slurm', action='store_true', help='submit a SLURM job array instead of running locally')
    p.add_argument('--chunk', type=int, default=1, help='--slurm: runs per array task (default: 1)')
    p.add_argument('--partition', help='--slurm: partition to submit to')
    p.add_argument('--time', help='--slurm: each array task\'s time limit (sbatch --time, e.g. 30 or 1:00:00); a run '
                   'it stops continues from its last checkpoint in the next submission')
    p.add_argument('--checkpoint-every', type=int, metavar='K', help='a checkpoint every K ticks of each run (0: '
                   'none; default with --slurm: every %d min of a run\'s predicted time, at most --time / 3, none for '
                   'shorter runs; without --slurm: none)' % slurm.CHECKPOINT_MINUTES)
    p.add_argument('--compression', choices=est.COMPRESSIONS, default='bz2',
                   help='the records\' chunk compression (default: bz2, the smallest; lz4 takes about 1.7 times its '
                   'disk and much less time per tick, which decides the time of small swarms)')
    p.add_argument('--graph', action='store_true', help='each run through the node graph (a private master each)')
    p.add_argument('--dry-run', action='store_true',
                   help='print the plan, the records it would reject and the estimate; write nothing in OUT')
    p.add_argument('--precision', type=float, help='rounds of seeds until every group\'s 95 %% interval of final P '
                   'is within this fraction of its mean (e.g. 0.05), or the group has the cap (--runs or the file\'s)')
    p.add_argument('--start-runs', type=int, help='--precision: seeds per group in round 1 (default: min(cap, 3))')
    p.add_argument('--reuse', action='append', default=[], metavar='DIR',
                   help='another sweep folder (repeatable): a planned run it holds complete is hard-linked, not rerun')
    p.add_argument('--planned', action='append', default=[], metavar='FILE', help='--dry-run: count the runs of '
                   'another dry run\'s plan (its --plan-file) as found (paper --dry-run passes it)')
    p.add_argument('--plan-file', metavar='FILE', help='--dry-run: write the plan (KEY<TAB>words lines) to FILE')
    p.add_argument('--no-fork', action='store_true', help='run every run from tick 0 (no shared prefixes)')
    p.add_argument('--save-prefix', metavar='TICK', help='every run also saves its state after TICK (half: half the '
                   'run, a step_up\'s alpha -1), kept in OUT/checkpoints: a later sweep that reuses these runs '
                   '(--reuse) forks its step_up runs from them (paper gives it to ideal_64x32)')
    p.add_argument('--group-runs', help='a file of GROUP<TAB>RUNS lines: those groups\' seed counts (OUT/groups.tsv '
                   'names the groups; the others run --runs)')
    return p


def parse(argv):
    """The options, checked: a bad one exits 2 naming it."""
    a = options().parse_args(argv)
    if a.precision is not None and not 0 < a.precision < 1:
        fail('--precision must be a fraction in (0, 1), e.g. 0.05 (got %g)' % a.precision)
    if a.precision is not None and a.group_runs:
        fail('--precision chooses every group\'s seeds itself: give it or --group-runs, not both')
    if a.save_prefix is not None and not (a.save_prefix == 'half' or a.save_prefix.isdigit()):
        fail('--save-prefix %s: give half (half the run) or a tick, a whole number' % a.save_prefix)
    if a.save_prefix is not None and a.graph:
        fail('--save-prefix goes without --graph (a node graph run has no checkpoints)')
    if (a.planned or a.plan_file) and not a.dry_run:
        fail('--planned and --plan-file go with --dry-run (a real sweep reuses records: --reuse DIR)')
    for folder in a.reuse:
        if not os.path.isfile(os.path.join(folder, 'runs.tsv')) or not os.path.isdir(os.path.join(folder, 'runs')):
            fail('--reuse %s is not a sweep folder (it has no runs.tsv and runs/)' % folder)
    for path in a.planned:
        if not os.path.isfile(path):
            fail('--planned %s: no such plan file (a --plan-file of an earlier dry run)' % path)
    if a.time is not None:
        if not a.slurm:
            fail('--time goes with --slurm (the time limit of each array task)')
        try:
            a.time_seconds = slurm.seconds(a.time)
        except slurm.TimeError as err:
            fail(str(err))
    if a.checkpoint_every is not None and a.checkpoint_every < 0:
        fail('--checkpoint-every must be >= 0 ticks (0: no checkpoints; got %d)' % a.checkpoint_every)
    if a.start_runs is not None and a.precision is None:
        fail('--start-runs goes with --precision')
    for name in ('runs', 'max_size', 'ticks', 'jobs', 'chunk', 'start_runs'):
        v = getattr(a, name)
        if v is not None and v < 1:
            fail('--%s must be >= 1 (got %d)' % (name.replace('_', '-'), v))
    return a


def writable(folder):
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
    except OSError as err:
        fail('output folder %s is not writable: %s' % (folder, err.strerror))


def load(a):
    """The experiment file with the command line's overrides, checked."""
    try:
        sizes = [int(n) for n in a.sizes.split(',')] if a.sizes else None
    except ValueError:
        fail('--sizes must be comma-separated whole numbers (got %s)' % a.sizes)
    axes = {}
    for axis, option, text in (('noise', '--noise-levels', a.noise_levels), ('population', '--multipliers',
                                                                             a.multipliers)):
        try:
            axes[axis] = [float(v) for v in text.split(',')] if text else None
        except ValueError:
            fail('%s must be comma-separated numbers (got %s)' % (option, text))
    overrides = {'runs': a.runs, 'ticks': a.ticks, 'max_size': a.max_size, 'sizes': sizes,
                 'controllers': a.controllers.split(',') if a.controllers else None, 'model': a.model,
                 'quirks': a.quirks, 'models': a.models, **axes}
    try:
        exp = experiment_file.load(a.file, overrides)
    except ExperimentError as err:
        fail(str(err))
    if a.save_prefix is not None:
        try:
            a.save_prefix = forks.prefix_tick(a.save_prefix, exp['ticks'])
        except ValueError as err:
            fail(str(err))
    return exp


def terminated(*_):
    raise jobs.Terminated()


def main(argv=None):
    """The sweep command (this module's docstring); returns its exit status, or exits with it on bad input.
    SIGTERM and SIGHUP stop it as Ctrl-C does while it runs, and have their handlers back when it returns."""
    argv = sys.argv[1:] if argv is None else argv
    a = parse(argv)
    exp = load(a)
    out = os.path.abspath(a.out or os.path.join(PACKAGE, 'results', 'sweeps', exp['name']))
    if out in map(os.path.abspath, a.reuse):
        fail('--reuse %s is this sweep\'s own --out folder' % out)
    previous = {sig: signal.getsignal(sig) for sig in (signal.SIGTERM, signal.SIGHUP)}
    for sig, handler in previous.items():  # like Ctrl-C: clean up (a SIGHUP ignored by nohup stays so)
        if handler != signal.SIG_IGN:
            signal.signal(sig, terminated)
    try:
        return locked(a, argv, exp, out)
    finally:
        for sig, handler in previous.items():
            if handler is not None:
                signal.signal(sig, handler)


def locked(a, argv, exp, out):
    """The sweep under OUT's lock (a dry run only looks), its ends said and the lock released."""
    lock = rec.SweepLock(out)
    if a.dry_run:  # looks only: no folder, no lock, no deletion
        holder = rec.read_holder(out)
        if holder and rec.alive_here(holder) is not False:
            print('%s: %s is in use by sweep %s; this plan is as of now' % (PROG, out, rec.describe(holder)))
    else:
        writable(out)
        try:
            stale = lock.take(' '.join(shlex.quote(w) for w in [PROG] + argv))
        except rec.LockHeld as held:
            fail('%s is in use by sweep %s; one sweep per folder: wait for it, or stop it, or use another --out'
                 % (out, held), 3)
        if stale:
            rec.warn(PROG, 'taking over %s from sweep %s, which ended without releasing it (killed?)'
                     % (os.path.join(out, rec.LOCK), rec.describe(stale)))
    try:
        return rounds(a, exp, out) if a.precision else sweep(a, exp, out, rr.read_group_runs(a.group_runs)
                                                                if a.group_runs else None)
    except rr.GroupRunsError as err:
        fail(str(err))
    except jobs.Terminated:
        rec.warn(PROG, 'terminated; the same command resumes (finished runs are kept)')
        return 143
    except KeyboardInterrupt:
        rec.warn(PROG, 'interrupted; the same command resumes (finished runs are kept)')
        return 130
    except est.CalibrationFailed as err:
        fail(str(err), 1)
    except OSError as err:
        if err.errno not in (errno.ENOSPC, errno.EDQUOT):
            raise
        fail(rec.no_space(out, 0), 1)
    finally:
        lock.release()


def rounds(a, exp, out):
    """--precision: sweeps of growing per-group seed counts (rounds.precision_rounds)."""
    try:
        every = expand(exp)
    except ExperimentError as err:
        fail(str(err))
    session = Session()
    return rr.precision_rounds(exp['name'], out, every, a.precision, min(exp['runs'], a.start_runs or 3), exp['runs'],
                               lambda counts: sweep(a, exp, out, counts, session), a.dry_run, PROG)
