"""What the sweep tests share: the command, a tiny experiment file's text and a sweep call."""
import math
import signal
import subprocess

SWEEP = ['rosrun', 'swarm_forage', 'sweep']


def experiment_text(name, sizes, ticks, sample_interval, controllers=('crw', 'dpo'), runs=2, arena='32x16'):
    """An experiment file (docs/sweeps-and-study.md) for CRW and DPO in 32x16 with 2 seeds, unless told."""
    return ('name: %s\narena: %s\ncontrollers: [%s]\nsizes: [%s]\nruns: %d\nticks: %d\nsample_interval: %d\n'
            % (name, arena, ', '.join(controllers), ', '.join(str(n) for n in sizes), runs, ticks,
               sample_interval))


# Two controllers, two sizes, two seeds, 1,500 ticks: eight runs of a few seconds.
TINY = experiment_text('tiny', [4, 8], 1500, 500)


def sweep(*args, timeout=600):
    """`sweep ARGS`, its output and errors in stdout."""
    return subprocess.run(SWEEP + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=timeout)


def sigint_default():
    """preexec_fn for a sweep the test stops with SIGINT: a test started in the background of a script inherits
    SIGINT ignored, and so would the sweep (its runs, which set their own handlers, would still stop)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def percentile(values, q):
    """The q-quantile of values, interpolated linearly between order statistics (numpy's default): the
    tests' own computation of a bootstrap interval."""
    values = sorted(values)
    pos = q * (len(values) - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(values) - 1)
    return values[lo] + (values[hi] - values[lo]) * (pos - lo)
