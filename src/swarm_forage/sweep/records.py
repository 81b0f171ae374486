"""A sweep's folder: its lock and its records' verification (used by sweep.steps).

One sweep per folder: SweepLock holds an exclusive flock on OUT/sweep.lock for the sweep's life and
writes its holder (pid, host, start time, command) into it; the file is emptied, never removed, at a
clean exit (removing a flock file lets two processes lock two different files). A record counts only
if `verify` finds it whole and of the planned run; others are moved to OUT/runs/rejected/ with a
.reason file. Verified records are remembered by (key, size, mtime, model version) in OUT/verified.tsv
so that a restart reads only new or changed bags."""
import errno
import fcntl
import glob
import os
import shutil
import socket
import subprocess
import sys
import time

LOCK = 'sweep.lock'
CACHE = 'verified.tsv'
REJECTED = 'rejected'
PLAN = 'plan'  # OUT/plan/: links to the planned records, the folder run_tables reads


class LockHeld(Exception):
    pass


def read_holder(out):
    """The holder a lock file names ({} when there is none or it is unreadable)."""
    try:
        with open(os.path.join(out, LOCK)) as f:
            text = f.read()
    except OSError:
        return {}
    holder = dict(line.split(': ', 1) for line in text.splitlines() if ': ' in line)
    return holder if 'pid' in holder else {}


def describe(holder):
    return 'pid %s on %s since %s (%s)' % (holder.get('pid', '?'), holder.get('host', '?'), holder.get('start', '?'),
                                          holder.get('command', '?'))


def alive_here(holder):
    """True/False whether the holder's process is alive, None when it runs on another host."""
    if holder.get('host') != socket.gethostname():
        return None
    return pid_alive(int(holder['pid'])) if holder.get('pid', '').isdigit() else False


def pid_alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


class SweepLock:
    """The exclusive lock of a sweep's folder; `take` raises LockHeld naming the holder."""

    def __init__(self, out):
        self.path, self.fd = os.path.join(out, LOCK), None

    def take(self, command):
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            os.close(fd)
            if err.errno not in (errno.EAGAIN, errno.EACCES):
                raise
            holder = {}
            for _ in range(50):  # the holder writes its name just after it locks
                holder = read_holder(os.path.dirname(self.path))
                if holder:
                    break
                time.sleep(0.1)
            raise LockHeld(describe(holder) if holder else 'a sweep that has not yet written its name')
        stale = read_holder(os.path.dirname(self.path))
        text = 'pid: %d\nhost: %s\nstart: %s\ncommand: %s\n' % (
            os.getpid(), socket.gethostname(), time.strftime('%Y-%m-%d %H:%M:%S %z'), command)
        os.ftruncate(fd, 0)
        os.pwrite(fd, text.encode(), 0)
        os.fsync(fd)
        self.fd = fd
        return stale  # the holder of a sweep that ended without releasing (killed), or {}

    def release(self):
        if self.fd is not None:
            os.ftruncate(self.fd, 0)
            os.close(self.fd)  # closing releases the flock
            self.fd = None


def model_version():
    """(model_version, code) of this build: `run_experiment --version`."""
    proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--version'], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    words = dict(line.split(': ', 1) for line in proc.stdout.splitlines() if ': ' in line)
    if proc.returncode != 0 or not words.get('model_version', '').isdigit():
        raise RuntimeError('`run_experiment --version` did not give a model_version (exit %d): %s'
                           % (proc.returncode, proc.stdout.strip()[-500:]))
    return int(words['model_version']), words.get('code', '').strip('"')


def verify(path, run, version, reused_label=None):
    """'' when the bag at `path` is the whole record of `run` made by model `version`, else why not; its
    label is the run's key, or `reused_label` for a record another sweep made (reuse)."""
    from swarm_forage.bags import runs  # here: `sweep --help` must not need ROS
    try:
        counts, msgs = runs.record_contents(path)
    except runs.BagError as err:
        return 'cannot be read: %s' % err
    if counts['/world/run_info'] != 1 or counts['/world/run_end'] != 1:
        return 'holds %d world/run_info and %d world/run_end messages (want 1 and 1)' % (
            counts['/world/run_info'], counts['/world/run_end'])
    if counts['/world/provenance'] != 1:
        return 'holds %d world/provenance messages (want 1: made by code older than model versions?)' % (
            counts['/world/provenance'])
    info, prov, end = msgs['/world/run_info'], msgs['/world/provenance'], msgs['/world/run_end']
    if not end.complete or end.ticks_done != end.ticks:
        return 'incomplete: world/run_end says %d of %d ticks (%s)' % (end.ticks_done, end.ticks, end.reason)
    if counts['/world/performance'] != run['ticks']:
        return 'holds %d ticks of world/performance (want %d)' % (counts['/world/performance'], run['ticks'])
    for field, want in (('controller', run['controller']), ('swarm_size', run['n']), ('seed', run['seed']),
                        ('ticks', run['ticks'])):
        if getattr(info, field) != want:
            return 'world/run_info %s is %s (the plan wants %s)' % (field, getattr(info, field), want)
    if run.get('identity') and info.identity != run['identity']:
        return 'world/run_info identity is %s (the plan wants %s: an input changed since it was recorded)' % (
            info.identity, run['identity'])
    if prov.label not in (run['key'], reused_label):
        return 'world/provenance label is %r (want the record key %r)' % (prov.label, run['key'])
    if prov.model_version != version:
        return 'made by model version %d (%s); this code is model version %d' % (prov.model_version, prov.code,
                                                                                version)
    return ''


class Records:
    """The planned records in OUT/runs: which are done, which are rejected, what is left over."""

    def __init__(self, out, version, dry_run, labels=None):
        self.out, self.runs, self.version, self.dry_run = out, os.path.join(out, 'runs'), version, dry_run
        self.cache, self.labels = {}, labels or {}  # labels: {key: label} of records reused from elsewhere
        try:
            with open(os.path.join(out, CACHE)) as f:
                for line in f:
                    words = line.rstrip('\n').split('\t')
                    if len(words) == 4:
                        self.cache[words[0]] = tuple(words[1:])
        except OSError:
            pass

    def stamp(self, path):
        st = os.stat(path)
        return (str(st.st_size), str(st.st_mtime_ns), str(self.version))

    def check(self, runs):
        """Splits `runs` into (done, rejected [(run, reason)]); non-dry: rejected records are moved aside."""
        done, rejected = [], []
        for r in runs:
            path = os.path.join(self.runs, r['key'] + '.bag')
            if not os.path.isfile(path):
                continue
            if self.cache.get(r['key']) == self.stamp(path):
                done.append(r)
                continue
            why = verify(path, r, self.version, self.labels.get(r['key']))
            if why:
                rejected.append((r, why))
                if not self.dry_run:
                    self.reject(r['key'], why)
            else:
                done.append(r)
                self.cache[r['key']] = self.stamp(path)
        if not self.dry_run:
            self.save()
        return done, rejected

    def reject(self, key, why):
        """Moves KEY.bag to runs/rejected/ (a free name) with KEY.reason beside it."""
        folder = os.path.join(self.runs, REJECTED)
        os.makedirs(folder, exist_ok=True)
        stem, k = os.path.join(folder, key), 1
        while os.path.exists(stem + '.bag') or os.path.exists(stem + '.reason'):
            stem, k = os.path.join(folder, '%s.%d' % (key, k)), k + 1
        os.rename(os.path.join(self.runs, key + '.bag'), stem + '.bag')
        with open(stem + '.reason', 'w') as f:
            f.write('%s.bag rejected by sweep %s: %s\n' % (key, time.strftime('%Y-%m-%d %H:%M:%S'), why))
        self.cache.pop(key, None)

    def save(self):
        tmp = os.path.join(self.out, CACHE + '.%d' % os.getpid())
        try:
            with open(tmp, 'w') as f:
                f.write(''.join('%s\t%s\n' % (k, '\t'.join(v)) for k, v in sorted(self.cache.items())))
            os.replace(tmp, os.path.join(self.out, CACHE))
        except OSError:
            if os.path.exists(tmp):  # a disk that filled: no partial cache left behind
                os.remove(tmp)
            raise

    def clear_leftovers(self, runs):
        """Removes partial records of planned runs whose writer is gone; returns [(path, pid)] still written."""
        busy = []
        for r in runs:
            stem = os.path.join(self.runs, r['key'])
            for path in glob.glob(glob.escape(stem) + '.bag*.active') + [stem + '_incomplete.bag']:
                pid = path[len(stem) + 5:-7]  # KEY.bag.<pid>.active
                if pid.isdigit() and pid_alive(int(pid)):
                    busy.append((path, int(pid)))  # another writer's: its no-clobber close settles who wins
                elif os.path.exists(path) and not self.dry_run:
                    os.remove(path)
        return busy

    def unplanned(self, runs):
        planned = {r['key'] + '.bag' for r in runs}
        return sorted(n for n in os.listdir(self.runs) if n.endswith('.bag') and n not in planned) \
            if os.path.isdir(self.runs) else []

    def link_plan(self, runs):
        """OUT/plan/ holds a link to each planned record and nothing else: run_tables reads only these."""
        folder = os.path.join(self.out, PLAN)
        os.makedirs(folder, exist_ok=True)
        for name in os.listdir(folder):
            os.remove(os.path.join(folder, name))
        for r in runs:
            if os.path.isfile(os.path.join(self.runs, r['key'] + '.bag')):
                os.symlink(os.path.join('..', 'runs', r['key'] + '.bag'), os.path.join(folder, r['key'] + '.bag'))
        return folder


def missing_records(out):
    """(missing, planned): how many of the sweep folder's planned runs (OUT/runs.tsv, written by its last call)
    have no record in OUT/runs; (0, 0) for a folder without a plan (tables made by hand)."""
    try:
        with open(os.path.join(out, 'runs.tsv')) as f:
            keys = [line.split('\t', 1)[0] for line in f if line.strip()]
    except OSError:
        return 0, 0
    return sum(not os.path.isfile(os.path.join(out, 'runs', k + '.bag')) for k in keys), len(keys)


def incomplete(folders):
    """'DIR: N of M planned records missing' for each sweep folder that lacks some."""
    out = []
    for folder in folders:
        missing, planned = missing_records(folder)
        if missing:
            out.append('%s: %d of %d planned records missing' % (folder, missing, planned))
    return out


def warn(prog, message):
    print('%s: %s' % (prog, message), file=sys.stderr, flush=True)


def no_space(out, todo):
    """What to say when OUT's disk is full: the folder, the space free and what the `todo` runs left need
    (the records kept so far give the size of one)."""
    def size(b):
        return '%d KiB' % (b // 1024) if b < 10 << 20 else '%d MiB' % (b >> 20)
    runs = os.path.join(out, 'runs')
    sizes = [e.stat().st_size for e in os.scandir(runs) if e.name.endswith('.bag')] if os.path.isdir(runs) else []
    need = ' the %d runs left need about %s (records here average %s);' % (
        todo, size(todo * sum(sizes) // len(sizes)), size(sum(sizes) // len(sizes))) if sizes and todo else ''
    return ('no space left on the device of %s (%s free):%s the records kept are whole and nothing partial counts '
            'as done; free space and run the same command again: it continues'
            % (out, size(shutil.disk_usage(out).free), need))
