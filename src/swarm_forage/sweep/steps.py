"""One sweep, step by step: plan its runs, check the records there, find those held elsewhere and the forks,
say what it will do and how long it will take, run what is missing, verify the records and make the tables.
`sweep` exits through fail() on bad input, as the command does."""
import dataclasses
import os
import subprocess
import sys
from typing import Optional

from swarm_forage.experiment import ExperimentError
from swarm_forage.experiment.plan import expand, graph_words
from swarm_forage.graph import launch_args
from swarm_forage.paths import PACKAGE
from swarm_forage.sweep import estimate as est
from swarm_forage.sweep import forks, jobs, reuse, slurm
from swarm_forage.sweep import records as rec
from swarm_forage.sweep import rounds as rr

PROG = 'sweep'


def fail(message, code=2):
    print('%s: %s' % (PROG, message), file=sys.stderr)
    sys.exit(code)


@dataclasses.dataclass
class Session:
    """What one sweep keeps for the next of the same command (the rounds of --precision): the runs were
    checked, whether run_experiment can fork, and the calibration."""
    checked: bool = False
    can_fork: Optional[bool] = None
    calibration: Optional[tuple] = None


@dataclasses.dataclass
class Plan:
    """One sweep's runs and what became of them: done (verified records), to do, found in other folders,
    forks (fork_plan, their extra words), the kept prefix (tick, runs) and the runs' cost."""
    runs: list
    version: int
    code: str
    records: rec.Records
    done: list
    todo: list
    found: list = dataclasses.field(default_factory=list)
    saves: set = dataclasses.field(default_factory=set)
    fork_plan: list = dataclasses.field(default_factory=list)
    extra: dict = dataclasses.field(default_factory=dict)
    prefix: Optional[tuple] = None
    cost: object = None


def sweep(a, exp, out, counts=None, session=None):
    """One sweep of `exp` with seeds 1 ... counts[group] (else exp['runs']); `session` keeps the check and the
    calibration from one round to the next."""
    session = Session() if session is None else session
    p = plan(a, exp, out, counts, session)
    forks_of(a, exp, out, p, session)
    if a.plan_file:
        write_plan_file(a.plan_file, p)
    announce(a, exp, p)
    estimate(a, exp, out, p, session)
    if a.dry_run:
        return 0
    problems = run(a, exp, out, p)
    if problems is None:
        return 130
    return finish(exp, out, p, problems)


def plan(a, exp, out, counts, session):
    """The runs and their words, checked once per session; the records there (verified, rejected, another
    plan's, leftovers) and those found in other folders (--reuse, --planned)."""
    try:
        runs = expand(exp, counts)
        declared = graph_args() if a.graph else None
        # The words run_one.sh passes on: run_experiment's, which refuses to start when the identity the plan
        # expects is no longer the run's (an input changed during the sweep), or forage's with --graph.
        for r in runs:
            r['words'] = graph_words(r['args'], declared) if a.graph \
                else r['args'] + ['expect_identity:=' + r['identity']]
        version, code = rec.model_version()
    except (ExperimentError, RuntimeError) as err:
        fail(str(err))
    if not session.checked:
        check_runs(exp, runs)
        session.checked = True
    records = rec.Records(out, version, a.dry_run, reuse.labels(out))
    done, rejected = records.check(runs)
    busy = records.clear_leftovers(runs)
    for path, pid in busy:
        rec.warn(PROG, '%s is being written by pid %d, not by this sweep; left alone' % (path, pid))
    done_keys = {r['key'] for r in done}
    p = Plan(runs, version, code, records, done, [r for r in runs if r['key'] not in done_keys])
    if rejected:
        rec.warn(PROG, '%d records %s to %s and redone: %s' % (
            len(rejected), 'would be moved' if a.dry_run else 'moved',
            os.path.join(out, 'runs', rec.REJECTED), reasons(rejected)))
    others = records.unplanned(runs)
    if others:
        rec.warn(PROG, '%d records in %s are not in this plan (another plan, arena or controller file): kept, left '
                 'out of the tables (e.g. %s)' % (len(others), os.path.join(out, 'runs'), others[0]))
    if not a.dry_run:
        os.makedirs(os.path.join(out, 'runs'), exist_ok=True)
    try:
        p.found = reuse.take(a.reuse, a.planned, exp, out, version, p.todo, records, a.dry_run, PROG)
    except reuse.ReuseError as err:
        fail(str(err))
    p.todo = [r for r in p.todo if r['key'] not in {f['key'] for f in p.found}]
    reuse.mark_reused(runs, out)
    return p


def forks_of(a, exp, out, p, session):
    """The forks at alpha (runs that start from a shared prefix's checkpoint) and --save-prefix's kept
    checkpoints, when this build's run_experiment can fork (asked once per session)."""
    p.saves = forks.checkpointable(exp['controllers'])
    p.fork_plan = [] if a.no_fork or a.graph else forks.plan(p.runs, {r['key'] for r in p.todo}, p.saves, out)
    if session.can_fork is None:
        session.can_fork = est.can_checkpoint()
    p.extra = forks.mark(p.fork_plan, out) if session.can_fork else {}
    if a.save_prefix and session.can_fork:
        p.prefix = (a.save_prefix, forks.save_prefixes(p.todo, p.extra, out, a.save_prefix, p.saves))


def write_plan_file(path, p):
    """--plan-file: the plan (KEY<TAB>words lines), and beside it the tick of the prefix it keeps."""
    with open(path, 'w') as f:
        f.write(''.join('\t'.join([r['key']] + r['words']) + '\n' for r in p.runs))
    if p.prefix:
        with open(path + '.prefix', 'w') as f:
            f.write('%d\n' % p.prefix[0])
    elif os.path.exists(path + '.prefix'):
        os.remove(path + '.prefix')


def workers(a):
    return 1 if a.slurm else a.jobs * max(1, len(a.sshlogin))


def announce(a, exp, p):
    """The sweep's line: its runs, done, found and to do, and what they are."""
    axes = ''.join(' x %d %s' % (len(exp[axis]), what) for axis, what in (
        ('noise', 'noise settings'), ('population', 'population settings'), ('models', 'models')) if len(exp[axis]) > 1)
    settings = [m['model'] + (' + ' + ','.join(m['quirks']) if m['quirks'] else '') for m in exp['models']]
    model = 'model %s' % settings[0] if len(settings) == 1 else '%d models (%s)' % (len(settings), ', '.join(settings))
    seeds = sorted({sum(1 for r in p.runs if r['group'] == g) for g in rr.group_names(p.runs)})
    print('%s: %s: %d runs (%d done, %s%d to do): %s x %s x N=%s x %d conditions%s x %s seeds, %d ticks each; '
          '%s; model version %d (%s)' % (
              PROG, exp['name'], len(p.runs), len(p.done), '%d found elsewhere, ' % len(p.found) if p.found else '',
              len(p.todo), exp['arena'], ','.join(exp['controllers']),
              ','.join(map(str, exp['sizes'])), len(exp['conditions']), axes,
              seeds[0] if len(seeds) == 1 else '%d-%d' % (seeds[0], seeds[-1]), exp['ticks'], model, p.version,
              p.code),
          flush=True)


def estimate(a, exp, out, p, session):
    """The calibration (once: a later round reuses it), the plan in numbers and the runs that write periodic
    checkpoints."""
    if p.todo:  # the calibration times only the controllers and models still to run
        if not {est.cost_key(r) for r in p.todo} <= set((session.calibration or ({},))[0]):
            session.calibration = est.calibrate(p.todo, exp['ticks'],
                                                1 if a.slurm else min(a.jobs, os.cpu_count() or 1), a.compression)
        calibration = session.calibration
        p.cost = lambda r: est.run_cost(r, calibration[0], calibration[1])  # noqa: E731
    print(est.plan_lines(PROG, exp, p.runs, p.done, p.found, p.todo, p.fork_plan, session.can_fork,
                         session.calibration, workers(a), a.graph, os.path.join(out, 'runs'), p.prefix), flush=True)
    unsaved = sorted({r['controller'] for r in p.todo if forks.step_tick(r) is not None} - p.saves)
    if unsaved and session.can_fork and not a.no_fork and not a.graph:
        print('%s: forks: %s cannot be checkpointed: %s step_up runs start from tick 0' % (
            PROG, ', '.join(unsaved), 'its' if len(unsaved) == 1 else 'their'), flush=True)
    periodic = slurm.choose(a.checkpoint_every, a.slurm, getattr(a, 'time_seconds', None), out, p.todo,
                            session.calibration, p.extra, p.saves)
    if periodic:
        print('%s: checkpoints: %d runs write one every %s ticks (a stopped run continues from it)' % (
            PROG, len(periodic), '/'.join(map(str, sorted(set(periodic.values()))))), flush=True)


def run(a, exp, out, p):
    """Runs what is to do, the other runs first and then the forks (they wait for their sources'
    checkpoints); returns the problems, or None when interrupted."""
    if p.prefix:
        forks.keep(out, p.prefix[0])
    jobs.write_plan(out, p.runs, p.todo, exp, a.graph, est.run_threads(1 if a.slurm else a.jobs), p.extra,
                    a.compression)
    changed = os.path.join(out, jobs.CHANGED)
    if os.path.exists(changed):
        os.remove(changed)
    problems = []
    if p.todo:
        progress = est.Progress(out, p.todo, p.cost)
        for listing in ('todo.txt', forks.TODO):
            if not os.path.getsize(os.path.join(out, listing)):
                continue
            result = jobs.run_slurm(out, a, progress, listing, lambda: p.records.clear_leftovers(p.todo)) \
                if a.slurm else jobs.run_local(out, a, progress, listing)
            if result is None:
                left = len(p.todo) - progress.update(final=True)
                rec.warn(PROG, 'interrupted; %d runs left; the same command resumes (finished runs are kept)' % left)
                return None
            problem, stop = job_problem(a, out, p, progress, result, changed)
            problems += [problem] if problem else []
            if stop:
                break
        slurm.remove_done(out, [r['key'] for r in p.todo])
    forks.remove_used(out, p.runs, p.prefix[0] if p.prefix else None)  # also a stopped call's, once spent
    return problems


def job_problem(a, out, p, progress, result, changed):
    """(what went wrong in one listing's jobs or None, whether the sweep stops): inputs that changed or a full
    disk stop it; failed runs do not (the forks still run, from tick 0 if their source failed)."""
    code, err = result
    if os.path.exists(changed):
        with open(changed) as f:
            keys = f.read().split()
        return ('the inputs changed during the sweep: %d runs refused to start, their identity no longer the planned '
                'one (e.g. %s; an arena, series or constants file was edited); the records made before are of the '
                'plan; the next call plans anew' % (len(keys), keys[0] if keys else '?')), True
    if code != 0 and 'No space left on device' in err:
        left = len(p.todo) - progress.update(final=True)
        return rec.no_space(out, left), True
    if code != 0:
        return '%s exited with %d%s' % ('sbatch' if a.slurm else 'parallel', code,
                                        (': ' + err.strip()[-2000:]) if err.strip() else ''), False
    return None, False


def finish(exp, out, p, problems):
    """Every planned record verified and the tables made, or the problems said; the exit status."""
    done, rejected = p.records.check(p.runs)
    if rejected:
        problems.append('%d records of this sweep rejected (moved to %s): %s' % (
            len(rejected), os.path.join(out, 'runs', rec.REJECTED), reasons(rejected)))
    done_keys = {r['key'] for r in done}
    missing = [r['key'] for r in p.runs if r['key'] not in done_keys]
    if missing:
        problems.append('%d runs did not finish (e.g. %s)' % (len(missing), missing[0]))
    problems += tables(out, exp, p.runs, p.records)
    if not problems:
        rr.write_groups(out, p.runs)
    if problems:
        for problem in problems:
            rec.warn(PROG, 'problem: ' + problem)
        rec.warn(PROG, '%s finished with %d problems (above); the same command redoes what is missing'
                 % (exp['name'], len(problems)))
        return 1
    print('%s: %s complete: %d runs in %s' % (PROG, exp['name'], len(p.runs), out))
    return 0


def check_runs(exp, runs):
    """run_experiment check:=true on the largest run of each controller, condition and robustness setting:
    bad parameters and sizes that do not fit the arena stop the sweep before anything runs."""
    seen = set()
    for r in sorted(runs, key=lambda r: -r['n']):
        what = (r['controller'], r['condition'], r['noise'], r['population'], r['model'])
        if what in seen:
            continue
        seen.add(what)
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'check:=true'] + r['args'],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0:
            fail('%s: %s N=%d %s: %s' % (exp['name'], r['controller'], r['n'],
                                         ' '.join(x for x in what[1:] if x),
                                         proc.stdout.strip().replace('run_experiment: ', '')))


def graph_args():
    """The arguments foraging.launch declares, with those of the files it includes with pass_all_args, as
    `forage` reads them (what a --graph run can be given)."""
    return set(launch_args.arg_names(os.path.join(PACKAGE, 'launch', 'foraging.launch')))


def reasons(rejected):
    return '; '.join('%s: %s' % (r['key'], why) for r, why in rejected[:5]) + \
        (' ...' if len(rejected) > 5 else '')


def tables(out, exp, runs, records):
    """run_tables over the planned records (OUT/plan). Its lines about records (a bag it cannot read, runs
    that cannot be combined) are problems of the sweep, and a record it cannot read is rejected, to be
    redone by the next call; its lines about metrics the plan cannot give (no smaller N for e, P = 0)
    are printed as notes."""
    planned = records.link_plan(runs)
    proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', planned, 'out:=' + os.path.join(out, 'tables'),
                           'sample_interval:=%d' % exp['sample_interval']],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    print(proc.stdout.strip())
    lines = [line.replace('run_tables: ', '', 1) for line in proc.stderr.splitlines() if line.strip()]
    problems, notes = [], []
    for line in lines:
        name = line.split(': ', 1)[0]
        if name.endswith('.bag'):
            problems.append('run_tables: ' + line)
            key = os.path.basename(name)[:-4]
            if os.path.isfile(os.path.join(out, 'runs', key + '.bag')):
                records.reject(key, 'run_tables: ' + line.split(': ', 1)[-1])
        elif 'cannot be combined' in line or proc.returncode != 0:  # e.g. "no usable recorded run"
            problems.append('run_tables: ' + line)
        else:
            notes.append(line)
    if proc.returncode != 0:
        problems.append('run_tables exited %d: no table written' % proc.returncode)
    if notes:
        print('%s: %d metrics this plan cannot give (run_tables; not a fault of the records):\n  %s'
              % (PROG, len(notes), '\n  '.join(notes)))
    records.save()
    return problems
