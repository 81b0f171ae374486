"""Runs that outlive a SLURM time limit (sweep --slurm): periodic checkpoints and resubmission.

With --slurm every run long enough gets `checkpoint_every:=K checkpoint:=OUT/checkpoints/KEY.checkpoint`
(run_experiment writes the whole state there every K ticks, atomically). A task that hits its time
limit (`--time`) is sent SIGTERM, writes a last checkpoint and keeps its bag segments (no record yet);
`run_one.sh` starts a run whose checkpoint exists with `resume:=` it, so the sweep resubmits the runs still without a record as a new
array, for as long as each submission moves on (a new record, or a checkpoint written since the last
one): a run that fails without moving on is not resubmitted forever. The checkpoint of a run is
removed once its record is there."""
import os
import re

CHECKPOINT_MINUTES = 10  # default: a checkpoint every 10 min of a run's predicted time (at most --time / 3)


class TimeError(ValueError):
    pass


def seconds(limit):
    """sbatch --time's value in seconds: MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS."""
    m = re.fullmatch(r'(?:(\d+)-)?(\d+)(?::(\d+))?(?::(\d+))?', limit or '')
    if not m:
        raise TimeError('--time %r is not a SLURM time (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS)' % limit)
    d, a, b, c = (int(x) if x else None for x in m.groups())
    if d is not None:  # D-HH[:MM[:SS]]
        total = d * 86400 + a * 3600 + (b or 0) * 60 + (c or 0)
    elif c is not None:
        total = a * 3600 + b * 60 + c
    else:
        total = a * 60 + (b or 0)
    if total < 60:
        raise TimeError('--time %s is under a minute, SLURM\'s smallest limit' % limit)
    return total


def every(run, per_tick, limit=None):
    """Ticks between checkpoints of `run` (0: none, it is short): one per CHECKPOINT_MINUTES of its
    predicted time, or per third of the time limit when that is shorter, in whole thousands of ticks."""
    interval = CHECKPOINT_MINUTES * 60.0 if limit is None else min(CHECKPOINT_MINUTES * 60.0, limit / 3.0)
    ticks = int(interval / max(per_tick, 1e-12)) // 1000 * 1000
    ticks = max(ticks, 1000)
    return ticks if ticks < run['ticks'] else 0


def choose(given, on_slurm, limit, out, todo, calibration, extra, saves):
    """{key: K} of the runs of `todo` that write a checkpoint every K ticks (their words go into `extra`):
    `given` (--checkpoint-every) or, on SLURM, `every` from the calibration's cost per tick; only runs of
    the controllers in `saves` (those that can be checkpointed)."""
    from swarm_forage.sweep import estimate as est  # here: estimate imports this module (via jobs)
    chosen = {}
    for r in todo:
        if r['controller'] not in saves:
            k = 0
        elif given is not None:
            k = given if given < r['ticks'] else 0
        elif on_slurm and calibration:
            fixed, slope = calibration[0][est.cost_key(r)]
            k = every(r, fixed + slope * r['n'], limit)
        else:
            k = 0
        if k:
            chosen[r['key']] = k
            extra.setdefault(r['key'], []).extend(words(out, r, k))
    return chosen


def checkpoint(out, key):
    return os.path.join(out, 'checkpoints', key + '.checkpoint')


def words(out, run, k):
    return ['checkpoint_every:=%d' % k, 'checkpoint:=' + checkpoint(out, run['key'])] if k else []


def state(out, keys):
    """What a submission can move: the records there and each checkpoint's mtime."""
    done = {k for k in keys if os.path.isfile(os.path.join(out, 'runs', k + '.bag'))}
    stamps = {}
    for k in keys:
        try:
            stamps[k] = os.stat(checkpoint(out, k)).st_mtime_ns
        except OSError:
            pass
    return done, stamps


def moved(before, after):
    """Whether a submission moved on: a new record, or a checkpoint new or rewritten since `before`."""
    return bool(after[0] - before[0]) or any(before[1].get(k) != v for k, v in after[1].items())


def remove_done(out, keys):
    for k in keys:
        if os.path.isfile(os.path.join(out, 'runs', k + '.bag')) and os.path.exists(checkpoint(out, k)):
            os.remove(checkpoint(out, k))


# run_one.sh's lines: a run with a checkpoint of its own continues from it (instead of tick 0 or its
# fork's source), and a source whose save at alpha is already written does not save it again.
RESUME = r'''ck=%s/"$key".checkpoint
if [ -f "$ck" ]; then  # stopped after a checkpoint (a SLURM time limit, a kill): continue from it
  kept=()
  for w in "${args[@]}"; do
    case $w in
      resume:=*) ;;
      save:=*) [ -f "${w#save:=}" ] || kept+=("$w") ;;
      *) kept+=("$w") ;;
    esac
  done
  save_done=1; for w in "${kept[@]}"; do [[ $w == save:=* ]] && save_done=0; done
  args=()
  for w in "${kept[@]}"; do [[ $save_done = 1 && $w == save_at:=* ]] || args+=("$w"); done
  args+=("resume:=$ck")
fi
'''
