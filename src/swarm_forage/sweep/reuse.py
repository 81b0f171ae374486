"""No run computed twice (sweep --reuse DIR): a planned run that another sweep folder already holds,
complete, is hard-linked into this sweep's records instead of being run again.

Two runs are the same run when their keys are equal: a key is the record's name as the core gives it
(controller, arena, N, condition, seed and the run identity, which holds every input that changes the run,
files by content), so an edited arena, series or constants file gives other keys and is never reused.

A found record must be whole (records.verify, its label the other folder's key) or already
verified by that folder's sweep with this model version (its verified.tsv). It is hard-linked, so it
stays valid when it is the only copy (the other folder deleted, moved or its record rejected: a link
is a name of the same file, not a pointer to the other name) and takes no space; across file systems
it is copied. OUT/reused.tsv names the reused records (KEY, the label they carry, the source)."""
import errno
import os
import shutil

from swarm_forage.sweep import records as rec

REUSED = 'reused.tsv'


def read_table(path):
    """[(key, words)] of a runs.tsv (a sweep's plan), [] when there is none."""
    try:
        with open(path) as f:
            return [(w[0], w[1:]) for w in (line.rstrip('\n').split('\t') for line in f) if len(w) > 1]
    except OSError:
        return []


def read_reused(folder):
    """{key: (label, source)} of a sweep folder's reused.tsv."""
    out = {}
    try:
        with open(os.path.join(folder, REUSED)) as f:
            for line in f:
                w = line.rstrip('\n').split('\t')
                if len(w) == 3:
                    out[w[0]] = (w[1], w[2])
    except OSError:
        pass
    return out


def read_prefix(plan_file):
    """The tick at which the runs of a planned sweep save a kept checkpoint (--save-prefix), or None: the
    plan file's companion PLAN.prefix (sweep --plan-file writes it)."""
    try:
        with open(plan_file + '.prefix') as f:
            return int(f.read().strip())
    except (OSError, ValueError):
        return None


class ReuseError(ValueError):
    pass


class Finder:
    """The runs other sweep folders hold (and, for a dry run, the plans of sweeps not yet run), by key."""

    def __init__(self, folders, exp, out, planned=()):
        self.found = {}  # key -> (folder, key, label, prefix tick); folder None: planned by another sweep
        self.names = []
        for folder in folders:
            folder = os.path.abspath(folder)
            if folder == os.path.abspath(out):
                raise ReuseError('--reuse %s is this sweep\'s own --out folder' % folder)
            if not os.path.isdir(os.path.join(folder, 'runs')) or not os.path.isfile(os.path.join(folder, 'runs.tsv')):
                raise ReuseError('--reuse %s is not a sweep folder (it has no runs.tsv and runs/)' % folder)
            self.names.append(folder)
            labels = read_reused(folder)
            for key, _ in read_table(os.path.join(folder, 'runs.tsv')):
                self.found.setdefault(key, (folder, key, labels.get(key, (key,))[0], None))
        for path in planned:
            if not os.path.isfile(path):
                raise ReuseError('--planned %s: no such plan file' % path)
            self.names.append(path)
            prefix = read_prefix(path)
            for key, _ in read_table(path):
                self.found.setdefault(key, (None, key, key, prefix))

    def lookup(self, run):
        return self.found.get(run['key'])


def whole(folder, key, label, run, version):
    """'' when FOLDER/runs/KEY.bag is a complete record of `run` (verified there by this model version, or
    verified now), else why not."""
    path = os.path.join(folder, 'runs', key + '.bag')
    if not os.path.isfile(path):
        return 'no record'
    cached = rec.Records(folder, version, True)
    if cached.cache.get(key) == cached.stamp(path):
        return ''
    return rec.verify(path, dict(run, key=label), version)


def link(src, dst):
    """dst as a hard link of src (a copy across file systems); never replaces dst."""
    try:
        os.link(src, dst)
        return 'linked'
    except OSError as err:
        if err.errno != errno.EXDEV:  # another file system
            raise
    tmp = '%s.%d.active' % (dst, os.getpid())  # a partial copy is a leftover the next sweep removes
    shutil.copyfile(src, tmp)
    os.link(tmp, dst)
    os.remove(tmp)
    return 'copied'


def reuse(finder, todo, out, version, dry_run):
    """Links every run of `todo` found complete elsewhere; returns (found runs, {source: count}, refused
    [(run, why)]). A dry run links nothing (and counts runs another sweep of the same call will make)."""
    found, sources, refused, lines = [], {}, [], []
    for r in todo:
        hit = finder.lookup(r)
        if not hit:
            continue
        folder, key, label, prefix = hit
        if folder is None:  # planned by a sweep before this one (paper --dry-run)
            r['found_in'] = (None, key, prefix)
            found.append(r)
            sources['planned'] = sources.get('planned', 0) + 1
            continue
        why = whole(folder, key, label, r, version)
        if why:
            refused.append((r, '%s: %s' % (os.path.join(folder, 'runs', key + '.bag'), why)))
            continue
        if not dry_run:
            link(os.path.join(folder, 'runs', key + '.bag'), os.path.join(out, 'runs', r['key'] + '.bag'))
            lines.append('%s\t%s\t%s\n' % (r['key'], label, os.path.join(folder, 'runs', key + '.bag')))
        r['found_in'] = (folder, key, None)  # where a checkpoint it kept may be (forks.kept)
        found.append(r)
        sources[folder] = sources.get(folder, 0) + 1
    if lines:
        path = os.path.join(out, REUSED)
        kept = read_reused(out)
        tmp = '%s.%d' % (path, os.getpid())
        with open(tmp, 'w') as f:
            f.write(''.join('%s\t%s\t%s\n' % (k, l, s) for k, (l, s) in sorted(kept.items())) + ''.join(lines))
        os.replace(tmp, path)
    return found, sources, refused


def mark_reused(runs, out):
    """Sets found_in on the runs this sweep's folder already holds as reused records (reused.tsv), as
    reuse() does on the runs it links now: a later call forks from a checkpoint their sweep kept too."""
    by_key = {r['key']: r for r in runs}
    for key, (_, source) in read_reused(out).items():
        if key in by_key and source.endswith('.bag'):
            by_key[key]['found_in'] = (os.path.dirname(os.path.dirname(source)), os.path.basename(source)[:-4], None)


def labels(out):
    """{key: the label its reused record carries} of this sweep's folder."""
    return {k: v[0] for k, v in read_reused(out).items()}


def take(folders, planned, exp, out, version, todo, records, dry_run, prog):
    """The runs of `todo` found complete in `folders` (linked into OUT/runs unless a dry run, and known to
    `records` as verified) or, for a dry run, in `planned` plans; prints how many and from where."""
    if not (folders or planned) or not todo:
        return []
    found, sources, refused = reuse(Finder(folders, exp, out, planned), todo, out, version, dry_run)
    for r, why in refused[:5]:
        rec.warn(prog, 'not reused (run instead): %s' % why)
    if not dry_run:
        records.labels.update(labels(out))
        for r in found:
            records.cache[r['key']] = records.stamp(os.path.join(out, 'runs', r['key'] + '.bag'))
        records.save()
    print('%s: reuse: %d of the %d runs to do found complete elsewhere%s%s%s' % (
        prog, len(found), len(todo), ' (would be hard-linked)' if dry_run else ' (hard-linked, not rerun)',
        ''.join('; %d in %s' % (n, 'the plans of earlier sweeps (--planned)' if s == 'planned' else s)
                for s, n in sorted(sources.items())), '; %d found but not whole, run again' % len(refused)
        if refused else ''), flush=True)
    return found
