"""The run library `recommend` decides from: sweep folders (sweep --out) with their tables, checked whole, read
into one map of groups, and the `sweep` commands that would measure what a target needs and they lack.

A group is (arena, controller, N, waveform, beta) as in tables/bootstrap.csv (ideal: waveform 'null'); its
values: P (the last sample's P_mean of series.csv) with a 95 % interval (tables/bootstrap.csv through
swarm_forage.study.bootstrap when the sweep has it, else P_mean -/+ P_ci95 of series.csv, clipped at 0), runs (seeds),
e (scalability.csv, N2 = N), Z (self_organization.csv Z_mean), R and A (flexibility.csv)."""
import glob
import math
import os
import shlex

from swarm_forage.bags import runs
from swarm_forage.robustness import tables as robustness_tables
from swarm_forage.study import bootstrap


# The tables every sweep folder of the library must hold (run_tables writes each, a header only where no group
# has rows: flexibility.csv of an ideal-only sweep); `paper --publish` copies them all.
TABLES = ('series', 'scalability', 'self_organization', 'flexibility')


class LibraryError(Exception):
    """The library lacks data or holds incomplete sweeps (`recommend` exits 1)."""


def is_sweep(folder):
    """Whether FOLDER is a sweep folder: it has tables/series.csv."""
    return os.path.isfile(os.path.join(folder, 'tables', 'series.csv'))


def expand(folders):
    """The sweep folders of the folders given: a sweep folder as it is; a study folder (`paper`'s OUT, or its
    copy made by `paper --publish`, e.g. docs/paper_96) as the sweep folders one level inside it, sorted. A
    folder that is neither stays as given, for `incomplete` to name."""
    out = []
    for f in folders:
        inner = [] if is_sweep(f) or not os.path.isdir(f) else sorted(
            os.path.join(f, d) for d in os.listdir(f) if is_sweep(os.path.join(f, d)))
        out += inner or [f]
    return list(dict.fromkeys(out))


def default_sweeps(package):
    """The folders under PACKAGE/results (one or two levels down: results/paper_quick/ideal_32x16,
    results/sweeps/NAME) that hold tables/series.csv, sorted."""
    results = os.path.join(package, 'results')
    found = glob.glob(os.path.join(results, '*', 'tables', 'series.csv')) + \
        glob.glob(os.path.join(results, '*', '*', 'tables', 'series.csv'))
    return sorted(os.path.dirname(os.path.dirname(p)) for p in found)


def planned(folder):
    """[(key, {word: value})] of the sweep's plan (FOLDER/runs.tsv), [] when it has none."""
    path = os.path.join(folder, 'runs.tsv')
    if not os.path.isfile(path):
        return []
    out = []
    with open(path) as f:
        for line in f:
            words = line.rstrip('\n').split('\t')
            out.append((words[0], dict(w.split(':=', 1) for w in words[1:] if ':=' in w)))
    return out


def incomplete(folder):
    """'' when the sweep folder is whole (tables written, every planned run recorded), else what is not."""
    if not os.path.isdir(folder):
        return 'no such folder'
    missing = [t for t in TABLES if not os.path.isfile(os.path.join(folder, 'tables', t + '.csv'))]
    if missing:
        return 'no tables/%s.csv (the sweep did not finish)%s' % (
            missing[0], '; nor is it a study folder (none of its folders holds tables/series.csv)'
            if missing[0] == 'series' else '')
    plan = planned(folder)
    absent = [k for k, _ in plan if not os.path.isfile(os.path.join(folder, 'runs', k + '.bag'))]
    if absent:
        return '%d of %d planned runs have no record (e.g. %s)' % (len(absent), len(plan), absent[0])
    return ''


def _float(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


class Library:
    def __init__(self, folders):
        self.folders = list(folders)
        self.groups = {}  # (arena, controller, N, waveform, beta) -> dict
        self.robustness = []  # robustness.tables points of every folder
        self.notes = []
        bad = [(f, incomplete(f)) for f in self.folders]
        bad = [(f, why) for f, why in bad if why]
        if bad:
            raise LibraryError('incomplete sweeps in the library (a sweep counts when its tables are written and '
                               'every planned run is recorded; run the same `rosrun swarm_forage sweep` command '
                               'again to finish it, or leave the folder out):\n  ' +
                               '\n  '.join('%s: %s' % fw for fw in bad))
        for f in self.folders:
            self._read(f)
        if not self.groups and self.robustness:
            self.notes.append('only robustness sweeps given: no ideal or time-varying groups to rank')

    def _read(self, folder):
        """Reads one folder's groups into a map of its own, then takes each group whole from the folder with the
        most seeds for it (first given on a tie): two sweeps of one group (e.g. ideal_64x32 and the ideal
        references of time_varying_64x32) never mix their e (against another smaller N) or runs. A robustness
        sweep (groups under noise or population dynamics in robustness.csv) gives its robustness points only:
        those groups share the plain groups' keys, and its plain groups are shorter runs."""
        points = robustness_tables.read(folder)
        if points:
            self.robustness += points
            return
        mine = {}

        def group(r, n):
            w = r['waveform']
            key = (r['arena'], r['controller'], int(n), w, float(r['beta']) if w != 'null' else 0.0)
            return mine.setdefault(key, {'folder': folder, 'P': None, 'lo': None, 'hi': None, 'interval': '',
                                         'runs': 0, 'e': None, 'Z': None, 'R': None, 'A': None})
        last = {}
        for r in runs.sweep_table(folder, 'series'):
            k = (r['arena'], r['controller'], r['swarm_size'], r['waveform'], r['beta'])
            if k not in last or int(r['sample']) > int(last[k]['sample']):
                last[k] = r
        for r in last.values():
            g = group(r, r['swarm_size'])
            g['P'], g['runs'], g['T'] = float(r['P_mean']), int(r['runs']), int(r['tick_end']) + 1
            half = _float(r['P_ci95'])
            if half is not None and g['runs'] > 1:
                g['lo'], g['hi'], g['interval'] = max(0.0, g['P'] - half), g['P'] + half, 't'
        for name, size, fields in (('scalability', 'N2', (('e', 'e'),)), ('self_organization', 'm_i', (('Z', 'Z_mean'),)),
                                   ('flexibility', 'N', (('R', 'R'), ('A', 'A')))):
            for r in runs.sweep_table(folder, name):
                if r['valid'] == '1':
                    g = group(r, r[size])
                    for field, column in fields:
                        g[field] = _float(r[column])
        try:
            draws = bootstrap.read(folder)
        except bootstrap.BootstrapMissing:
            rel = os.path.relpath(folder)  # as the reader named it: the note is the same from any clone
            self.notes.append('%s has no tables/bootstrap.csv: P intervals there are Student t (series.csv P_ci95)'
                              % (folder if rel.startswith(os.pardir) else rel))
            draws = None
        if draws is not None:
            for key in draws.groups():
                g = mine.get(key)
                column = draws.metric(key, 'P')
                if g is not None and column:
                    est, lo, hi, n = bootstrap.interval(column)
                    if n >= 2:
                        g['lo'], g['hi'], g['interval'] = max(0.0, lo), hi, 'bootstrap'
        for key, g in mine.items():
            old = self.groups.get(key)
            if old is None or g['runs'] > old['runs']:
                self.groups[key] = g

    def sizes(self, arena, controller, waveform='null', beta=0.0, metric='P'):
        return sorted(n for (a, c, n, w, b), g in self.groups.items()
                      if (a, c, w) == (arena, controller, waveform) and (w == 'null' or b == beta)
                      and g[metric] is not None)

    def controllers(self, arena):
        return sorted({c for (a, c, _, w, _) in self.groups if a == arena and w == 'null'})

    def arenas(self):
        return sorted({k[0] for k in self.groups})

    def folder_of(self, arena, waveform):
        """A sweep folder of the library holding groups of that arena and waveform ('null': ideal), or None."""
        return next((g['folder'] for (a, _, _, w, _), g in sorted(self.groups.items()) if a == arena
                     and w == waveform), None)


def experiment_file(package, folder, arena, time_varying):
    """(path, True) of the experiment file a sweep folder was made from, known by the folder's name (the
    layout of `paper`: results/paper_quick/ideal_64x32); else (the package's file of that kind and arena, False);
    (None, False) when there is none (the command then writes one)."""
    files = os.path.join(package, 'config', 'experiments')
    name = os.path.basename(os.path.normpath(folder)) if folder else ''
    if name and os.path.isfile(os.path.join(files, name + '.yaml')):
        return os.path.join(files, name + '.yaml'), True
    path = os.path.join(files, '%s_%s.yaml' % ('time_varying' if time_varying else 'ideal', arena))
    return (path, False) if os.path.isfile(path) else (None, False)


def sweep_command(package, library, arena, sizes, controllers, conditions=()):
    """The `rosrun swarm_forage sweep ...` command (a shell text, possibly with the experiment file it needs
    written first) that measures `controllers` at `sizes` in `arena` under ideal conditions or under
    each of `conditions` [(waveform, beta)] with their ideal references. Into an existing sweep's folder (named
    after its experiment file, as `paper` names them, and holding its plan runs.tsv, so its records) it lists
    that sweep's sizes and controllers too, with its seeds and ticks, so that its records are reused and its
    tables keep them. Any other folder (a copy of a sweep's tables, as docs/paper_96 holds, or a folder not
    known by its name) is left alone: the command then writes a sweep of its own (the default --out) of the
    sizes and controllers asked, with the ticks of the library's groups, which `recommend` reads with the
    others."""
    time_varying = bool(conditions)
    folder = library.folder_of(arena, conditions[0][0] if time_varying else 'null')
    plan = planned(folder) if folder else []
    path, same = experiment_file(package, folder, arena, time_varying)
    into = bool(folder and same and plan)
    if into:
        old = {int(w['n_robots']) for _, w in plan if 'n_robots' in w} | \
            {k[2] for k, g in library.groups.items() if g['folder'] == folder}
        seeds = max([int(w['seed']) for _, w in plan if w.get('seed', '').isdigit()] or [0])
        ticks = {w['ticks'] for _, w in plan if 'ticks' in w}
        controllers = sorted(set(controllers) | {w['controller'] for _, w in plan if 'controller' in w})
    else:
        old, seeds = set(), 0
        ticks = {str(g['T']) for k, g in library.groups.items() if k[0] == arena and g.get('T')
                 and (folder is None or g['folder'] == folder)}
        controllers = sorted(set(controllers))
    words = ['rosrun', 'swarm_forage', 'sweep']
    pre = ''
    if path is None:
        name = 'time_varying_%s%s' % (arena, '_' + conditions[0][0] if len(conditions) == 1 else '')
        path = name + '.yaml'
        pre = ('cat > %s <<EOF\nname: %s\narena: %s\ncontrollers: [%s]\nsizes: [%s]\nruns: 10\nticks: 50000\n'
               'sample_interval: 1000\nconditions:\n  - {waveform: "null"}\n%sparams:\n  gp_dpo/estimates: '
               'time_varying\nEOF\n' % (path, name, arena, ', '.join(controllers), ', '.join(map(str, sizes)),
                                        ''.join('  - {waveform: %s, beta: %g, alpha: -1}\n' % c for c in conditions)))
    inside = path.startswith(package + os.sep)  # the package's file, wherever the command is run from
    words.append(os.path.relpath(path, package) if inside else path)
    words += ['--sizes', ','.join(str(n) for n in sorted(set(sizes) | old)), '--controllers', ','.join(controllers)]
    words += ['--runs', str(seeds or 10)]  # a new sweep: 10 seeds, not the file's 50
    if len(ticks) == 1:
        words += ['--ticks', ticks.pop()]
    if into:  # the sweep's own file into its folder: its records are reused, its tables grow
        words += ['--out', folder]
    text = ' '.join(shlex.quote(w) for w in words)
    return pre + (text.replace(' config/', ' $(rospack find swarm_forage)/config/', 1) if inside else text)
