"""Shared prefixes run once (sweep side of forked runs): a step_up run is the ideal run until its alpha,
so of the runs that differ only in such a condition one runs from tick 0 and saves a checkpoint at alpha
(`save_at:=T save:=FILE`), and the others continue from it (`resume:=FILE`): each such fork costs
ticks - T, not ticks. run_experiment refuses a fork whose condition is not the source's up to T (exit 2),
so this module only chooses the pairs; it does not decide equality of series itself beyond "step_up is 0
before alpha" (condition.cpp, Condition::value).

The source of a family (one controller, N, seed and every other word) and save tick is its ideal run
when that is still to do, else its first step_up run still to do; a sweep runs the sources (and every
run that is no fork) first, then the forks (sweep: two rounds of GNU Parallel or two job arrays).

A sweep whose ideal runs another sweep reuses (time_varying_64x32 reuses ideal_64x32's) can save them for
it too: with `sweep --save-prefix half` every run it makes also saves its state at half the run, kept in
OUT/checkpoints; the later sweep, finding the record (--reuse), forks every step_up run of that family
from the kept checkpoint instead of running one of them from tick 0.

Only the runs of controllers that can be checkpointed (`run_experiment --controllers`: checkpointable)
fork or save; the others run from tick 0."""
import os

from swarm_forage.experiment import kinds

CONDITION = ('waveform', 'beta', 'alpha', 'frequency', 'phase', 'offset', 'target', 'series')
KEPT = 'checkpoints_kept.txt'  # OUT/: the ticks of --save-prefix, whose checkpoints are kept
CHECKPOINTS = 'checkpoints'  # OUT/checkpoints/<source key>_at<T>.checkpoint, removed when its forks are done
TABLE = 'forks.tsv'  # OUT/forks.tsv: KEY<TAB>extra run_experiment words (save_at/save or resume)
TODO = 'todo_forks.txt'  # the forks still to do, run after every other run


def words_of(run):
    return dict(w.split(':=', 1) for w in run['args'])


def step_tick(run):
    """The tick of a step_up run's step (its alpha, -1 = half the run), or None for any other run."""
    w = words_of(run)
    if w.get('waveform') != 'step_up':
        return None
    alpha = float(w.get('alpha', '-1'))
    if alpha < 0:
        return run['ticks'] // 2  # condition.cpp: alpha in [-1, 0) is half the run
    tps = float(w.get('ticks_per_second', '5'))  # WorldConfig's default: 5 ticks per second
    return int(alpha * tps)


def family(run):
    w = words_of(run)
    return tuple(sorted((k, v) for k, v in w.items() if k not in CONDITION))


PLANNED = '(the checkpoint a planned sweep will save)'  # a dry run's stand-in for a kept checkpoint


def prefix_tick(value, ticks):
    """--save-prefix VALUE as a tick in [1, ticks): 'half' (a step_up's alpha -1) or a whole number."""
    tick = ticks // 2 if value == 'half' else int(value) if str(value).isdigit() else 0
    if not 0 < tick < ticks:
        raise ValueError('--save-prefix %s: give half or a tick in [1, %d) (the runs have %d ticks)'
                         % (value, ticks, ticks))
    return tick


def kept(run, tick):
    """The checkpoint at `tick` another sweep kept of `run` (a record found there: run['found_in'], set by
    reuse), PLANNED when a planned sweep will keep it (a dry run), or None."""
    folder, key, planned_tick = run.get('found_in') or (None, None, None)
    if key is None:
        return None
    if folder is None:
        return PLANNED if planned_tick == tick else None
    path = os.path.join(folder, CHECKPOINTS, '%s_at%d.checkpoint' % (key, tick))
    return path if os.path.isfile(path) else None


def checkpointable(controllers):
    """The controllers of `controllers` whose runs can be saved and resumed, from the registry's listing."""
    return {c for c in controllers if kinds.controller_kind(c).get('checkpointable', False)}


def plan(runs, todo_keys, saves, folder=None):
    """[(source run, save tick, [fork runs], kept checkpoint or None)] of the runs still to do (`todo_keys`)
    of the controllers in `saves` (those that can be checkpointed); with a kept checkpoint the source is the
    ideal run another sweep made, or this one (OUT's own checkpoint of a call that was stopped before its
    forks ran), and every run forks."""
    families = {}
    for r in runs:
        if r['controller'] not in saves:
            continue
        f = families.setdefault(family(r), {'ideal': None, 'steps': {}})
        if words_of(r).get('waveform') in (None, 'null'):
            f['ideal'] = r
        else:
            tick = step_tick(r)
            if tick is not None and tick > 0:
                f['steps'].setdefault(tick, []).append(r)
    out = []
    for f in families.values():
        ideal = f['ideal']
        ideal_free = ideal is not None and ideal['key'] in todo_keys
        for tick, members in sorted(f['steps'].items()):
            todo = [r for r in members if r['key'] in todo_keys]
            path = (kept(ideal, tick) or own(folder, ideal, tick)) if ideal is not None and not ideal_free else None
            source = ideal if ideal_free or path else (todo[0] if todo else None)
            forks = [r for r in todo if r is not source]
            if source is None or not forks:
                continue
            ideal_free = ideal_free and source is not ideal  # one save_at per run
            out.append((source, tick, forks, path))
    return out


def checkpoint(out, source, tick):
    return os.path.join(out, CHECKPOINTS, '%s_at%d.checkpoint' % (source['key'], tick))


def own(out, run, tick):
    """OUT's checkpoint of `run` at `tick`, when an earlier call saved it, else None."""
    path = checkpoint(out, run, tick) if out else None
    return path if path and os.path.isfile(path) else None


def mark(forks, out):
    """Sets each fork's from_tick (the estimate's cost) and returns {key: extra words} for run_one.sh."""
    extra = {}
    for source, tick, runs, path in forks:
        if not path:
            path = checkpoint(out, source, tick)
            extra[source['key']] = ['save_at:=%d' % tick, 'save:=' + path]
        for r in runs:
            r['from_tick'] = tick
            extra[r['key']] = ['resume:=' + path]
    return extra


def write_table(out, extra):
    with open(os.path.join(out, TABLE), 'w') as f:
        f.write(''.join('\t'.join([k] + w) + '\n' for k, w in sorted(extra.items())))


def robot_ticks(run):
    return run['n'] * (run['ticks'] - run.get('from_tick', 0))


def save_prefixes(todo, extra, out, tick, saves):
    """--save-prefix: every run to do of a controller in `saves` that saves no checkpoint yet saves one at
    `tick`, to be kept (a run saves at one tick at most); returns how many."""
    n = 0
    for r in todo:
        if r['controller'] in saves and tick < r['ticks'] and \
                not any(w.startswith('save_at:=') for w in extra.get(r['key'], [])):
            extra[r['key']] = extra.get(r['key'], []) + ['save_at:=%d' % tick, 'save:=' + checkpoint(out, r, tick)]
            n += 1
    return n


def keep(out, tick):
    """Notes that OUT keeps its checkpoints at `tick` (--save-prefix), for later sweeps: remove_used leaves
    them, in later calls too."""
    if tick not in kept_ticks(out):
        with open(os.path.join(out, KEPT), 'a') as f:
            f.write('%d\n' % tick)


def kept_ticks(out):
    path = os.path.join(out, KEPT)
    if not os.path.isfile(path):
        return set()
    with open(path) as f:
        return {int(w) for w in f.read().split() if w.isdigit()}


def remove_used(out, runs, keep_tick=None):
    """Removes OUT's checkpoints of planned runs once every step run that could fork from them has its record
    (the rest stay for the next call, which forks from them), but those at `keep_tick` (--save-prefix);
    another sweep's kept checkpoints are that sweep's."""
    folder = os.path.join(out, CHECKPOINTS)
    if not os.path.isdir(folder):
        return
    planned = {r['key']: r for r in runs}
    keep = kept_ticks(out) | {keep_tick}
    families = {}
    for r in runs:
        families.setdefault(family(r), []).append(r)
    for name in os.listdir(folder):
        key, _, tick = name[:-len('.checkpoint')].rpartition('_at')
        if not name.endswith('.checkpoint') or key not in planned or not tick.isdigit() or int(tick) in keep:
            continue
        steps = [r for r in families[family(planned[key])] if step_tick(r) == int(tick) and r['key'] != key]
        if all(os.path.isfile(os.path.join(out, 'runs', r['key'] + '.bag')) for r in steps):
            os.remove(os.path.join(folder, name))
