"""A sweep's time estimate and progress bar (used by sweep.steps).

The calibration times short runs of each controller as the sweep will run them, on the machine as it
is now; so that a reader knows how far to trust it, the ceiling loop (bench_ceiling, a fixed workload)
runs just before and just after it and the load average is read: the spread of the two ceiling
figures is the spread of the machine's speed while it calibrated."""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from swarm_forage.sweep import jobs


# A record's tick-0 snapshot per robot, by compression: measured as the size difference of 1-tick records at
# N = 16 and 4,096 in 64x32 (bz2: CRW 11.9, GP-DPO 12.0 bytes; lz4 12.7; none 17.0); the calibration's own
# short records are too small to tell it from the rest (they gave 20 to 6,000 bytes).
SNAPSHOT_BYTES_PER_ROBOT = {'bz2': 12.0, 'lz4': 12.7, 'none': 17.0}
COMPRESSIONS = tuple(SNAPSHOT_BYTES_PER_ROBOT)  # run_experiment's compression:= values, bz2 first
STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}  # the sweep stops on each (sweep.cli)


class CalibrationFailed(Exception):
    pass


def run_threads(runs_at_once):
    """Worker threads per run when `runs_at_once` share this machine's cores."""
    return max(1, (os.cpu_count() or 1) // max(1, runs_at_once))


def ceiling():
    """Robot-ticks/s of the ceiling loop on one thread (1,024 robots in 32x16), or None."""
    proc = subprocess.run(jobs.program('bench_ceiling') + ['--n', '1024', '--arena', '32x16', '--ticks', '1000',
                                                                 '--threads', '1'],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    m = re.search(r': ([\d.e+]+) robot-ticks/s', proc.stdout)
    return float(m.group(1)) if proc.returncode == 0 and m else None


def cost_key(run):
    """What a run's cost per tick is calibrated for: its controller and model (the quirks change it several
    times over, e.g. light_occlusion in a crowd)."""
    return run['controller'], run.get('model', '')


def key_text(key):
    return key[0] + (' (%s)' % key[1] if key[1] else '')


class CalibrationRuns:
    """The calibration's short runs of run_experiment, in a folder of their own, `copies` at once as the sweep
    runs them; close() stops any still running and removes the folder."""

    def __init__(self, copies, compression):
        self.copies, self.compression = copies, compression
        self.folder, self.procs = None, []
        self.program = jobs.program('run_experiment')  # as run_one.sh starts it: without rosrun's lookup

    def make_folder(self):
        # The name first, then the folder: a signal (the sweep's SIGTERM handler raises) right after mkdtemp's
        # mkdir but before its result was assigned would leave the folder behind.
        self.folder = os.path.join(tempfile.gettempdir(),
                                   'swarm_forage_calibration_%d_%d' % (os.getpid(), time.time_ns()))
        os.mkdir(self.folder, 0o700)

    def timed(self, args, cal_ticks, n_copies=1):
        """(seconds, bytes of the first record) of `n_copies` runs at once of `cal_ticks` ticks."""
        bags = [os.path.join(self.folder, 'cal%d.bag' % k) for k in range(n_copies)]
        for bag in bags:
            if os.path.exists(bag):
                os.remove(bag)
        start = time.time()
        logs = []
        for bag in bags:  # each run's words to a file (a pipe could fill while the others run)
            logs.append(open(bag + '.log', 'w+'))
        try:
            self.procs[:] = []
            for bag, log in zip(bags, logs):
                self.start(args, cal_ticks, bag, log)
            self.check([p.wait() for p in self.procs], logs, args)
        finally:
            for log in logs:
                log.close()
        return time.time() - start, os.path.getsize(bags[0])

    def start(self, args, cal_ticks, bag, log):
        # A signal's handler raises at the next bytecode: one arriving while Popen starts a run would leave it
        # out of `procs`, unkilled, to recreate the folder after the cleanup. Held until listed.
        held = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        try:
            self.procs.append(subprocess.Popen(self.program + ['ticks:=%d' % cal_ticks, 'bag:=' + bag,
                                                               'compression:=' + self.compression,
                                                               'record_every:=%d' % cal_ticks,
                                                               'threads:=%d' % run_threads(self.copies)] + args,
                                               stdout=log, stderr=subprocess.STDOUT))
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)

    @staticmethod
    def check(codes, logs, args):
        """Raises CalibrationFailed with the first failed run's own reason, e.g. a parameter it refused."""
        failed = next((k for k, c in enumerate(codes) if c != 0), None)
        if failed is not None:
            logs[failed].seek(0)
            said = [line.strip() for line in logs[failed] if line.strip()]
            raise CalibrationFailed('the calibration run failed (exit %d): run_experiment %s: %s' % (
                codes[failed], ' '.join(args), ' / '.join(said[-3:]) or 'it said nothing'))

    def close(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
        if self.folder:
            shutil.rmtree(self.folder, ignore_errors=True)


def calibrate(runs, ticks, copies, compression='bz2'):
    """Each controller's (and model's: cost_key) cost per tick, fixed plus per robot, from short runs at its
    largest size and at 16 robots (start-up time apart), `copies` at once as the sweep runs them; the start-up
    time of one run; the record's bytes per tick and per robot (its tick-0 snapshot); and the machine's state
    around it: load average, and the ceiling loop's rate before and after."""
    machine = {'cores': os.cpu_count() or 1, 'load': os.getloadavg()[0], 'ceilings': [ceiling()],
               'compression': compression}
    cal = CalibrationRuns(copies, compression)
    try:
        cal.make_folder()
        startup, per_tick = record_costs(cal, machine)
        costs, per_robot = controller_costs(cal, runs, ticks, startup, per_tick)
        machine['ceilings'].append(ceiling())
    finally:  # also on Ctrl-C or SIGTERM: stop the runs, then remove their folder
        cal.close()
    return costs, startup, (per_tick, max(per_robot, 0.0)), machine


def record_costs(cal, machine):
    """(the start-up time of one run, the record's bytes per tick), from a lone robot's runs; into `machine`
    what the tables cost and what a checkpoint's join costs."""
    startup, one = sorted(cal.timed(['n_robots:=1'], 1) for _ in range(3))[1]
    per_tick = max(0.0, cal.timed(['n_robots:=1'], 5001)[1] - one) / 5000
    # A run that saves a checkpoint (a fork's source, a kept prefix) or starts from one (a fork) writes its
    # record in segments and joins them at its end (their chunks copied, the tick-0 one decoded): the same
    # lone robot's 20,000 ticks with and without a checkpoint half way, which carries the first half's record.
    whole = cal.timed(['n_robots:=1'], 20000)[0]
    machine['tables'] = tables_cost(cal.folder, os.path.join(cal.folder, 'cal0.bag'), 20000, startup)
    try:
        save = os.path.join(cal.folder, 'cal.checkpoint')
        split = cal.timed(['n_robots:=1', 'save_at:=10000', 'save:=' + save], 20000)[0]
        machine['join_per_tick'] = max(0.0, split - whole) / 20000
        machine['part_per_tick'] = os.path.getsize(save) / 10000
    except CalibrationFailed:  # a build without checkpoints: no joins either
        machine['join_per_tick'] = 0.0
    return startup, per_tick


def controller_costs(cal, runs, ticks, startup, per_tick):
    """(cost_key -> (seconds per tick, seconds per robot-tick), the record's largest bytes per robot) of the
    controllers (and models) of `runs`, each calibrated once, at its largest size."""
    costs, per_robot = {}, 0.0
    for r in sorted(runs, key=lambda r: -r['n']):
        if cost_key(r) in costs:
            continue
        args = [a for a in r['args'] if not a.startswith(('ticks:=', 'alpha:=', 'n_robots:='))]
        points, bytes_per_robot = cost_points(cal, args, r['n'], ticks, startup, per_tick)
        per_robot = max(per_robot, bytes_per_robot)
        (n0, c0), (n1, c1) = points[0], points[-1]
        slope = (c1 - c0) / (n1 - n0) if n1 > n0 else c1 / n1
        costs[cost_key(r)] = (max(c0 - slope * n0, 0.0), max(slope, 1e-12))
    return costs, per_robot


def cost_points(cal, args, n_max, ticks, startup, per_tick):
    """([(N, seconds per tick)] at min(n_max, 16) and n_max, the record's bytes per robot at n_max)."""
    # Cost per tick = fixed + per_robot_cost * N, from the largest size and a small one. The large size runs
    # 1.6e7 robot-ticks three times and keeps the median: with a run of 2e6 robot-ticks once, the start-up's
    # error and one slow second moved a sweep's estimate by 2x.
    points, bytes_per_robot = [], None
    for n in sorted({n_max, min(n_max, 16)}):
        cal_ticks = max(20, min(ticks, (16000000 if n > 16 else 2000000) // n))
        tries = [cal.timed(args + ['n_robots:=%d' % n], cal_ticks, cal.copies) for _ in range(3 if n > 16 else 1)]
        wall, size = sorted(tries)[len(tries) // 2]
        points.append((n, max(wall - startup, 1e-3) / cal_ticks))
        if n == n_max:
            bytes_per_robot = (size - per_tick * cal_ticks) / n
    return points, bytes_per_robot


def tables_cost(folder, bag, ticks, startup):
    """What the sweep's tables cost (run_tables on every core, after the runs): seconds of CPU per recorded tick
    read, from `bag` (`ticks` long), and per group and bootstrap draw, from 200 draws of its one group."""
    sub = os.path.join(folder, 'tables')
    os.mkdir(sub)
    os.link(bag, os.path.join(sub, 'run.bag'))

    def timed(draws):
        start = time.time()
        proc = subprocess.run(jobs.program('run_tables') + [sub, 'out:=' + os.path.join(sub, 'out'),
                                                                  'bootstrap:=%d' % draws],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.time() - start if proc.returncode == 0 else None

    read, drawn = timed(0), timed(200)
    if read is None or drawn is None:
        return None
    return {'per_tick': max(0.0, read - startup) / ticks, 'per_draw': max(0.0, drawn - read) / 200}


def tables_seconds(runs, groups, machine, draws=2000):
    """The tables' time: every planned record read (done, reused and new), and `draws` bootstrap draws of each
    group, on all cores."""
    cost = machine.get('tables')
    if not cost:
        return 0.0
    return (sum(r['ticks'] for r in runs) * cost['per_tick'] + groups * draws * cost['per_draw']) / machine['cores']


def run_cost(run, costs, startup):
    """Predicted seconds of one run: start-up plus ticks x (fixed + per robot x N); a fork's ticks are those
    after its checkpoint."""
    fixed, slope = costs[cost_key(run)]
    return startup + (run['ticks'] - run.get('from_tick', 0)) * (fixed + slope * run['n'])


def human(seconds):
    seconds = int(seconds)
    if seconds < 120:
        return '%d s' % seconds
    if seconds < 7200:
        return '%d min' % round(seconds / 60)
    return '%.1f h' % (seconds / 3600)


def how_sure(seconds, machine):
    """The estimate as a range from the ceiling loop's spread, with the load it was measured under."""
    rates = [c for c in machine['ceilings'] if c]
    where = 'measured under load %.1f on %d cores' % (machine['load'], machine['cores'])
    if len(rates) < 2:
        return '%s (%s; the ceiling loop did not run, so the spread is unknown)' % (human(seconds), where)
    spread = max(rates) / min(rates)
    return ('%s (%s to %s: the ceiling loop ran at %.3g and %.3g robot-ticks/s before and after the calibration; '
            '%s%s)' % (human(seconds), human(seconds / spread), human(seconds * spread), rates[0], rates[1], where,
                       '; a busy machine: a quiet one is faster' if machine['load'] > 0.5 * machine['cores'] else ''))


class Progress:
    """A bar weighted by each run's predicted cost (from the calibration), with an ETA from this
    sweep's rate so far: short runs, dominated by start-up, count as what they cost, not by robot-ticks."""

    def __init__(self, out, todo, cost):
        self.folder, self.todo, self.cost = os.path.join(out, 'runs'), todo, cost
        self.total = sum(cost(r) for r in todo) or 1.0
        self.start, self.last_line, self.fraction = time.time(), 0.0, 0.0
        self.tty = sys.stderr.isatty()

    def update(self, final=False):
        done = [r for r in self.todo if os.path.exists(os.path.join(self.folder, r['key'] + '.bag'))]
        elapsed = time.time() - self.start
        frac = self.fraction = min(1.0, sum(self.cost(r) for r in done) / self.total)
        eta = elapsed * (1 - frac) / frac if frac > 0 else float('nan')
        bar = '#' * int(30 * frac) + '.' * (30 - int(30 * frac))
        line = '[%s] %5.1f%%  %d/%d runs  %s elapsed%s' % (
            bar, 100 * frac, len(done), len(self.todo), human(elapsed),
            '' if final or frac == 0 else ', ETA %s' % human(eta))
        if self.tty:
            sys.stderr.write('\r' + line + ('\n' if final else ''))
            sys.stderr.flush()
        elif final or time.time() - self.last_line >= 30:
            print(line, file=sys.stderr, flush=True)
            self.last_line = time.time()
        return len(done)


def can_checkpoint():
    """Whether this build's run_experiment saves and resumes runs (save_at:=, resume:=)."""
    proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--help'], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    return 'resume' in proc.stdout and 'save_at' in proc.stdout


# A checkpoint's state (world, controllers, RNG counters), bz2 records apart, per robot: measured at
# N = 4,096 in 64x32, tick 100 (CRW 130, DPO 169 bytes).
CHECKPOINT_BYTES_PER_ROBOT = 170.0


def plan_lines(prog, exp, runs, done, found, todo, fork_plan, can_fork, calibration, workers, graph, folder,
               prefix=None):
    """The plan in numbers: runs, robot-ticks, forks, reuses, the time and the disk (`prefix`: (tick, runs)
    of --save-prefix, whose checkpoints are kept); and one `totals:` line of key=value words that paper
    --dry-run adds up."""
    n_forks = sum(len(f) for _, _, f, _ in fork_plan)
    ticks = sum(r['n'] * (r['ticks'] - (r.get('from_tick', 0) if can_fork else 0)) for r in todo)
    lines = ['%s: plan: %d runs: %d done, %d reused (found complete elsewhere), %d to do; %.3g robot-ticks to do' % (
        prog, len(runs), len(done), len(found), len(todo), ticks)]
    lines += fork_lines(prog, fork_plan, can_fork, folder, prefix)
    seconds = forked = disk = 0.0
    if calibration and todo:
        estimate, seconds, forked, disk = estimate_lines(prog, runs, todo, fork_plan, can_fork, calibration,
                                                         workers, graph, folder, prefix)
        lines += estimate
    lines.append('%s: totals: name=%s runs=%d done=%d reused=%d todo=%d forks=%d robot_ticks=%.6g seconds=%.0f '
                 'bytes=%.0f possible_forks=%d seconds_forked=%.0f' % (
                     prog, exp['name'], len(runs), len(done), len(found), len(todo), n_forks if can_fork else 0,
                     ticks, seconds, disk, n_forks, forked))
    return '\n'.join(lines)


def fork_lines(prog, fork_plan, can_fork, folder, prefix):
    """The plan's forks from shared prefixes, and the prefixes it keeps for a later sweep."""
    n_forks = sum(len(f) for _, _, f, _ in fork_plan)
    saved = sum(r['n'] * t for _, t, f, _ in fork_plan for r in f)
    n_kept = sum(1 for _, _, _, path in fork_plan if path)
    lines = []
    if fork_plan:
        lines.append('%s: forks: %d of the runs to do %s from %d checkpoints of shared prefixes (a step_up run is '
                     'the ideal run until alpha%s): %.3g robot-ticks %s' % (
                         prog, n_forks, 'start' if can_fork else 'could start', len(fork_plan),
                         '; %d of them kept by the sweep whose ideal runs are reused' % n_kept if n_kept else '',
                         saved, 'saved' if can_fork else 'not saved: this build\'s run_experiment has no '
                         'save_at:=/resume:='))
    if prefix and prefix[1]:
        lines.append('%s: prefixes: %d runs also save their state after tick %d, kept in %s for the step_up runs '
                     'of a later sweep that reuses them (--reuse) to fork from' % (
                         prog, prefix[1], prefix[0], os.path.join(os.path.dirname(folder), 'checkpoints')))
    return lines


def estimate_lines(prog, runs, todo, fork_plan, can_fork, calibration, workers, graph, folder, prefix):
    """(lines, seconds, seconds with forks, bytes) of the calibrated estimate: the time in its parts, and the
    records' disk."""
    costs, startup, size, machine = calibration
    fork_tick = {r['key']: t for _, t, f, _ in fork_plan for r in f}
    # The joins at the ends of the runs whose records are in segments: forks, sources, kept prefixes.
    split = set(fork_tick) | {source['key'] for source, _, _, path in fork_plan if not path}
    if prefix and prefix[1]:
        split |= {r['key'] for r in todo if prefix[0] < r['ticks']}
    joins = sum(machine.get('join_per_tick', 0.0) * r['ticks'] for r in todo if r['key'] in split) / workers
    forked = sum(run_cost(dict(r, from_tick=fork_tick.get(r['key'], 0)), costs, startup) for r in todo) / workers
    forked += joins
    lines = []
    if joins and can_fork:
        lines.append('%s: joins: %d runs write their records in segments (forks, their sources, kept prefixes) '
                     'and join them at their end, %.2g s per 1,000 ticks: %s of the estimate' % (
                         prog, len(split & {r['key'] for r in todo}), 1000 * machine['join_per_tick'], human(joins)))
    seconds = forked if can_fork else sum(run_cost(dict(r, from_tick=0), costs, startup) for r in todo) / workers
    # The tables read every planned record, after the runs, on this machine's cores.
    table_time = tables_seconds(runs, len({r['group'] for r in runs}), machine)
    seconds, forked = seconds + table_time, forked + table_time
    ran = [(r, r['ticks'] - (fork_tick.get(r['key'], 0) if can_fork else 0)) for r in todo]
    lines.append('%s: the estimate in parts: start-ups %s, each tick\'s fixed cost (the record, bookkeeping) %s, '
                 'the robots %s%s, the tables %s' % (
                     prog, human(startup * len(todo) / workers),
                     human(sum(costs[cost_key(r)][0] * t for r, t in ran) / workers),
                     human(sum(costs[cost_key(r)][1] * r['n'] * t for r, t in ran) / workers),
                     ', joins %s' % human(joins) if joins and can_fork else '',
                     human(table_time) if machine.get('tables') else 'not measured (run_tables failed)'))
    compression = machine.get('compression', 'bz2')
    snapshot = SNAPSHOT_BYTES_PER_ROBOT[compression]
    disk = records_bytes(todo, size, snapshot, machine, prefix)
    lines.append('%s: calibration: %s robot-ticks/s; estimated %s on %d %s%s; records ~%.0f MB (%s, one snapshot: '
                 '%.0f bytes per robot, %.2f per tick; reused records are links and take none) in %s' % (
                     prog, ', '.join('%s %.3g' % (key_text(c), 1.0 / v[1]) for c, v in sorted(costs.items())),
                     how_sure(seconds, machine), workers, 'slot' if workers == 1 else 'slots',
                     ' (headless)' if not graph else ' (headless rate; the graph is slower)', disk / 1e6,
                     compression, snapshot, size[0], folder +
                     (' and the kept checkpoints (%.0f bytes per robot more)' % CHECKPOINT_BYTES_PER_ROBOT
                      if prefix and prefix[1] else '')))
    return lines, seconds, forked, disk


def records_bytes(todo, size, snapshot, machine, prefix):
    """The disk the records of `todo` take (`size`: bytes per tick, per robot; `snapshot`: the tick-0 snapshot's
    bytes per robot), with the checkpoints --save-prefix keeps."""
    disk = sum(size[0] * r['ticks'] + snapshot * r['n'] for r in todo)
    if prefix and prefix[1]:  # the kept checkpoints: state and the record up to the tick
        part = machine.get('part_per_tick', size[0])  # their record so far, as the segments hold it
        disk += sum(part * prefix[0] + snapshot * r['n'] + CHECKPOINT_BYTES_PER_ROBOT * r['n']
                    for r in todo if prefix[0] < r['ticks'])
    return disk
