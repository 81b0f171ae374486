"""`recommend`: the (controller, N) a target calls for, ranked from a run library (docs/recommend.md).

Candidates are every controller of the target's arena at each measured N <= robots, and at the sizes its
fitted P(N) (recommend_model) gives between them and up to two doublings beyond (powers of two and N*,
<= robots; marked "fitted"). Each criterion is normalised across the candidates by min-max, 1 for the best and 0 for the worst
(P, Z and robustness higher-better; e, R and A lower-better; an undefined value scores 0), and the score is
the weighted mean sum(w_k s_k) / sum(w_k), in [0, 1]."""
import math
import os
import sys

from swarm_forage import claims
from swarm_forage import recommend_library as lib
from swarm_forage import recommend_model as model
from swarm_forage import recommend_target as target

PROG = 'recommend'
# criterion of the target's weights -> (candidate field, +1 higher is better / -1 lower is better, label)
CRITERIA = {'performance': ('P', 1, 'final P'), 'scalability': ('e', -1, 'e'),
            'self_organization': ('Z', 1, 'Z'), 'reactivity': ('R/P', -1, 'R/P'), 'adaptability': ('A/P', -1, 'A/P'),
            'robustness': ('Rob', 1, 'robustness')}
NORMALISATION = ('score = sum(w_k s_k) / sum(w_k); s_k = (x - worst) / (best - worst) across the candidates '
                 '(min-max: 1 best, 0 worst; P, Z, robustness higher-better, e, R/P, A/P lower-better; undefined = 0). '
                 'R and A are scored per block: divided by the ideal final P of their group, so that a large swarm is '
                 'not marked down for delivering more')


def nearest(sizes, n):
    """The size of `sizes` nearest `n` on a log scale (the larger on a tie), None when there is none."""
    return min(sizes, key=lambda m: (abs(math.log(m) - math.log(n)), -m)) if sizes else None


def flexibility(library, t, controller, n):
    """(R, A, R/P, A/P, where) for the target's conditions: the group of (arena, controller, N) under each, else
    the nearest N measured in the arena, else in the arena nearest in area; averaged over the conditions. P is the
    ideal final P of the group R and A come from."""
    values, where, lacking = [], [], []
    arenas = sorted(library.arenas(), key=lambda a: (a != t['arena'], abs(area(a) - t['area'])))
    for w, b in t['conditions']:
        if w == 'null':
            continue
        for a in arenas:
            m = nearest(library.sizes(a, controller, w, b, 'R'), n)
            if m is not None:
                g = library.groups[(a, controller, m, w, b)]
                p = library.groups.get((a, controller, m, 'null', 0.0), {}).get('P')
                values.append((g['R'], g['A'], g['R'] / p if p else None, g['A'] / p if p else None))
                if (a, m) != (t['arena'], n):
                    where.append('%s N=%d' % (a, m))
                break
        else:
            lacking.append('%s %g' % (w, b))
    if not values:
        return None, None, None, None, []
    notes = ['R, A of ' + ', '.join(sorted(set(where)))] if where else []
    notes += ['R, A without %s (not measured)' % ', '.join(lacking)] if lacking else []
    mean = [None if any(v[k] is None for v in values) else sum(v[k] for v in values) / len(values) for k in range(4)]
    return tuple(mean) + (notes,)


def area(name):
    w, h = (float(x) for x in name.split('x')) if 'x' in name else (0.0, 0.0)
    return w * h


def robustness(library, t, controller, n):
    """The mean normalised robustness (higher-better) of the controller nearest N and the target's noise level
    and rate multiplier, and where it comes from; (None, '') when not asked for or not measured."""
    chosen, where = [], []
    for measure, key, want in (('saa', 'noise_level', t['noise']), ('pd', 'multiplier', t['population'])):
        if want is None:
            continue
        pts = [p for p in library.robustness if p['measure'] == measure and p['controller'] == controller and p['valid']]
        if not pts:
            return None, ''
        level = min({p[key] for p in pts}, key=lambda v: abs(v - want))
        m = nearest(sorted({p['N'] for p in pts if p[key] == level}), n)
        sel = [p['normalized'] for p in pts if p[key] == level and p['N'] == m]
        chosen.append(sum(sel) / len(sel))
        where.append('%s %s %g N=%d %s' % (measure, key, level, m, pts[0]['arena']))
    return (sum(chosen) / len(chosen), ', '.join(where)) if chosen else (None, '')


def candidates(library, t):
    """(candidates, fits {controller: Fit or None}); candidates are dicts (see the module's docstring)."""
    out, fits = [], {}
    for c in library.controllers(t['arena']):
        sizes = library.sizes(t['arena'], c)
        groups = {n: library.groups[(t['arena'], c, n, 'null', 0.0)] for n in sizes}
        f = fits[c] = model.fit([(n, g['P'], g['runs']) for n, g in groups.items()])
        todo = [(n, 'measured') for n in sizes if n <= t['robots']]
        if f is not None:
            # between the measured sizes and up to two doublings beyond the largest (further is not a fit's job)
            extra = {2 ** k for k in range(40) if sizes[0] < 2 ** k <= min(t['robots'], 4 * sizes[-1])} - set(sizes)
            star = f.optimum()
            if star and sizes[0] < star <= min(t['robots'], 4 * sizes[-1]) and round(star) not in sizes:
                extra.add(int(round(star)))
            todo += [(n, 'fitted' if n < sizes[-1] else 'fitted beyond N=%d' % sizes[-1]) for n in sorted(extra)]
        for n, source in todo:
            d = {'controller': c, 'N': n, 'source': source, 'notes': []}
            if source == 'measured':
                g = groups[n]
                d.update(P=g['P'], lo=g['lo'], hi=g['hi'], runs=g['runs'], e=g['e'], Z=g['Z'], interval=g['interval'])
            else:
                d.update(P=f(n), lo=None, hi=None, runs=0, interval='')
                d['e'] = model.scalability(f(n / 2.0), f(n), n / 2.0, n) if n >= 2 else None
                zs = library.sizes(t['arena'], c, metric='Z')
                m = nearest(zs, n)
                d['Z'] = library.groups[(t['arena'], c, m, 'null', 0.0)]['Z'] if m else None
                if m:
                    d['notes'].append('Z of N=%d' % m)
            d['R'], d['A'], d['R/P'], d['A/P'], notes = flexibility(library, t, c, n)
            d['notes'] += notes
            d['Rob'], where = robustness(library, t, c, n)
            if where:
                d['notes'].append('robustness of ' + where)
            out.append(d)
    return out, fits


def score(cands, weights):
    """Sets each candidate's s_<criterion>, score and rank; returns the candidates ranked (ties: higher P)."""
    total = sum(weights.values())
    for crit, w in weights.items():
        field, sign, _ = CRITERIA[crit]
        vals = [d[field] for d in cands if d[field] is not None]
        best, worst = ((max(vals), min(vals)) if sign > 0 else (min(vals), max(vals))) if vals else (None, None)
        for d in cands:
            x = d[field]
            d['s_' + crit] = 0.0 if x is None else 1.0 if best == worst else (x - worst) / (best - worst)
    for d in cands:
        d['score'] = sum(w * d['s_' + k] for k, w in weights.items()) / total
    ranked = sorted(cands, key=lambda d: (-d['score'], -(d['P'] or 0), d['N']))
    for k, d in enumerate(ranked):
        d['rank'] = k + 1
    return ranked


def fmt(v, digits=4):
    if v is None:
        return 'n/a'
    return '{:,.0f}'.format(v) if abs(v) >= 1000 else '%.*g' % (digits, v)


def table(ranked, weights):
    head = ('rank', 'controller', 'N', 'P', '95% interval', 'seeds', 'e', 'Z', 'R', 'A', 'R/P', 'A/P') + \
        (('robust',) if 'robustness' in weights else ()) + ('score', 'source / notes')
    rows = []
    for d in ranked:
        iv = '[%s, %s]%s' % (fmt(d['lo']), fmt(d['hi']), ' t' if d['interval'] == 't' else '') \
            if d['lo'] is not None else '-'
        rows.append((str(d['rank']), d['controller'], str(d['N']), fmt(d['P']), iv, str(d['runs'] or '-'),
                     fmt(d['e'], 3), fmt(d['Z'], 3), fmt(d['R']), fmt(d['A']), fmt(d['R/P'], 3), fmt(d['A/P'], 3)) +
                    ((fmt(d['Rob'], 3),) if 'robustness' in weights else ()) +
                    ('%.3f' % d['score'], '; '.join([d['source']] + d['notes'])))
    widths = [max(len(r[k]) for r in rows + [head]) for k in range(len(head))]
    line = lambda r: '  '.join(x.rjust(wd) if k not in (1, len(head) - 1) else x.ljust(wd)  # noqa: E731
                               for k, (x, wd) in enumerate(zip(r, widths))).rstrip()
    return '\n'.join([line(head), line(['-' * wd for wd in widths])] + [line(r) for r in rows])


def reasons(ranked, weights, t):
    """The top choice in plain words, as the paper's section 5: what it wins on, with numbers, against the
    best candidate of every other controller."""
    top = ranked[0]
    n = len(ranked)
    out = ['Recommended: %s with N = %d in %s (score %.3f of 1, rank 1 of %d candidates; P %s).' % (
        top['controller'], top['N'], t['arena'], top['score'], n, top['source'])]
    if top['source'] != 'measured':
        out.append('  Its P is %s from the fit of P(N), not measured: measure it before deciding (below, Missing).'
                   % ('extrapolated' if 'beyond' in top['source'] else 'interpolated'))
    for crit in sorted(weights, key=lambda k: -weights[k]):
        field, sign, label = CRITERIA[crit]
        vals = sorted((d for d in ranked if d[field] is not None), key=lambda d: -sign * d[field])
        if top[field] is None:
            out.append('- %s (weight %g): not known for it (scores 0).' % (crit, weights[crit]))
            continue
        place = 1 + sum(1 for d in vals if sign * d[field] > sign * top[field])
        best = vals[0]
        words = '%s %s' % (label, fmt(top[field]))
        if crit == 'performance' and top['lo'] is not None:
            words += ' [%s, %s]' % (fmt(top['lo']), fmt(top['hi']))
        comp = 'the %s of all %d' % ('highest' if sign > 0 else 'lowest', len(vals)) if place == 1 else \
            'rank %d of %d (best: %s N=%d with %s)' % (place, len(vals), best['controller'], best['N'], fmt(best[field]))
        out.append('- %s (weight %g): %s, %s.' % (crit, weights[crit], words, comp))
    for c in sorted({d['controller'] for d in ranked} - {top['controller']}):
        other = next(d for d in ranked if d['controller'] == c)
        gaps = sorted(((weights[k] * (top['s_' + k] - other['s_' + k]) / sum(weights.values()), k) for k in weights),
                      reverse=True)
        diffs = ', '.join('%s %s vs %s' % (CRITERIA[k][2], fmt(top[CRITERIA[k][0]]), fmt(other[CRITERIA[k][0]]))
                          for k in weights)
        out.append('- against %s at its best, N = %d (rank %d, score %.3f): %s; %s trails most on %s (%.3f of the '
                   'score).' % (c, other['N'], other['rank'], other['score'], diffs, c, gaps[0][1], gaps[0][0]))
    return '\n'.join(out)


def to_measure(robots):
    """The sizes a sweep of a controller with no measured size within `robots` would measure: the three largest
    powers of two <= robots (enough for a fit of P(N), and e at the two larger)."""
    return [2 ** k for k in range(40) if robots / 8.0 < 2 ** k <= robots]


def missing(library, t, cands, package):
    """[(what is missing, the sweep command that would measure it)]: per controller of the target's arena, the
    sizes up to `robots` beyond its largest measured one, or, when none of its sizes is within `robots` (it has
    no candidate), the sizes that would give it some; then the conditions not measured."""
    out = []
    controllers = library.controllers(t['arena'])
    for c in controllers:
        sizes = library.sizes(t['arena'], c)
        if not [n for n in sizes if n <= t['robots']]:
            want = to_measure(t['robots'])
            out.append(('%s: no size measured within the target\'s %d robots in %s (measured: N = %s), so it is no '
                        'candidate; N = %s not measured' % (c, t['robots'], t['arena'], ','.join(map(str, sizes)),
                                                            ','.join(map(str, want))),
                        lib.sweep_command(package, library, t['arena'], want, [c])))
            continue
        beyond = [2 ** k for k in range(40) if sizes[-1] < 2 ** k <= t['robots']]
        if beyond:
            fitted = any(d['controller'] == c and d['source'] != 'measured' for d in cands)
            out.append(('%s: P measured in %s up to N = %d; the target allows %d robots: N = %s not measured%s' % (
                c, t['arena'], sizes[-1], t['robots'], ','.join(map(str, beyond)),
                ' (the fit stands in up to N = %d: two doublings)' % (4 * sizes[-1]) if fitted else
                ' (no fit of P(N) stands in: it needs 3 sizes)'),
                lib.sweep_command(package, library, t['arena'], beyond, [c])))
    absent = []
    for w, b in t['conditions']:
        if w == 'null':
            continue
        have = {n for c in controllers for n in library.sizes(t['arena'], c, w, b, 'R')}
        want = sorted({d['N'] for d in cands if d['source'] == 'measured'} - have)
        if not have:
            absent.append((w, b))
        elif want:
            out.append(('R and A of %s under %s beta %g not measured at N = %s (taken from the nearest measured '
                        'size, marked in the table)' % (t['arena'], w, b, ','.join(map(str, want))),
                        lib.sweep_command(package, library, t['arena'], want, controllers, [(w, b)])))
    if absent:
        want = sorted({d['N'] for d in cands if d['source'] == 'measured'})
        out.append(('no sweep of %s under %s (R and A taken from the arena nearest in area, or left out; marked in '
                    'the table)' % (t['arena'], ', '.join('%s beta %g' % c for c in absent)),
                    lib.sweep_command(package, library, t['arena'], want, controllers, absent)))
    # one command for what it measures together (into a sweep's folder: every controller of it)
    merged = {}
    for what, cmd in out:
        merged.setdefault(cmd, []).append(what)
    return [('; '.join(whats), cmd) for cmd, whats in merged.items()]


def main(argv, package):
    import argparse
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('target', help='target YAML (config/targets/*.yaml; keys: docs/recommend.md)')
    p.add_argument('sweeps', nargs='*', help='sweep folders (sweep --out), or study folders holding them (paper\'s '
                   'results/paper_96, its copy docs/paper_96); default: the folders under PACKAGE/results (one or '
                   'two levels down) that hold tables/')
    p.add_argument('--output', help='also write the text there')
    p.add_argument('--figure', help='the figure (PNG; default: next to --output, else ./recommend.png)')
    a = p.parse_args(argv)
    try:
        t = target.load(a.target)
        for k in ('reactivity', 'adaptability'):
            if t['weights'][k] > 0 and all(w == 'null' for w, _ in t['conditions']):
                raise target.TargetError('weights.%s needs conditions other than ideal (R and A measure a change)' % k)
    except target.TargetError as err:
        print('%s: %s: %s' % (PROG, a.target, err), file=sys.stderr)
        return 2
    folders = a.sweeps or lib.default_sweeps(package)
    try:
        if not folders:
            raise lib.LibraryError('no sweep folders given and none with tables/ under %s/results (run `make '
                                   'paper-quick` or a sweep, or name folders)' % package)
        library = lib.Library([os.path.abspath(f) for f in lib.expand(folders)])
        if t['arena'] not in library.arenas() or not library.controllers(t['arena']):
            raise lib.LibraryError('no sweep of the library covers arena %s (it covers %s); measure it with:\n  %s' % (
                t['arena'], ', '.join(library.arenas()) or 'none',
                lib.sweep_command(package, library, t['arena'], [2 ** k for k in range(40)
                                                                 if t['robots'] / 16 < 2 ** k <= t['robots']],
                                  sorted({k[1] for k in library.groups}) or list(claims.PAPER))))
        if (t['noise'] is not None or t['population'] is not None) and not library.robustness:
            raise lib.LibraryError('noise and population need robustness tables and no sweep of the library has '
                                   'any; measure them with:' + ''.join(
                                       '\n  rosrun swarm_forage sweep $(rospack find swarm_forage)/config/experiments/robustness_%s_32x16.yaml '
                                       '--runs 3' % m for k, m in (('noise', 'saa'), ('population', 'pd'))
                                       if t[k] is not None))
        cands, fits = candidates(library, t)
        if not cands:
            raise lib.LibraryError('no candidate with N <= %d robots in %s (smallest measured: %s); measure one with:'
                                   % (t['robots'], t['arena'], min(n for c in library.controllers(t['arena'])
                                                                   for n in library.sizes(t['arena'], c))) +
                                   ''.join('\n- %s:\n  %s' % (what, cmd.replace('\n', '\n  '))
                                           for what, cmd in missing(library, t, cands, package)))
    except (lib.LibraryError, lib.runs.TableMissing) as err:
        print('%s: %s' % (PROG, err), file=sys.stderr)
        return 1
    weights = {k: w for k, w in t['weights'].items() if w > 0}
    ranked = score(cands, weights)
    text = render(t, library, ranked, fits, weights, missing(library, t, cands, package))
    figure = a.figure or os.path.join(os.path.dirname(os.path.abspath(a.output)) if a.output else os.getcwd(),
                                      'recommend.png')
    from swarm_forage import recommend_figure
    recommend_figure.draw(figure, ranked, fits, library, t, weights)
    text += '\nFigure: %s\n' % shown(figure)
    if a.output:
        tmp = a.output + '.%d.tmp' % os.getpid()
        with open(tmp, 'w') as f:
            f.write(text)
        os.replace(tmp, a.output)
    print(text, end='')
    return 0


def shown(path):
    """A path as the output prints it: relative to the working folder when inside it (the command as typed)."""
    rel = os.path.relpath(os.path.abspath(path))
    return path if rel == os.pardir or rel.startswith(os.pardir + os.sep) else rel


def render(t, library, ranked, fits, weights, lacks):
    out = ['Target: ' + target.describe(t),
           'Weights: ' + ', '.join('%s %g' % kw for kw in weights.items()),
           'Library: ' + ', '.join(shown(f) for f in library.folders),
           'Normalisation: ' + NORMALISATION,
           'P: final P (blocks) of the ideal groups of %s, measured (95 %% bootstrap interval over seeds; "t": '
           'Student t of series.csv) or fitted; e, Z ideal; R, A under the target\'s conditions.' % t['arena'],
           '', table(ranked, weights), '', reasons(ranked, weights, t), '',
           'Fits of P(N) = a N^b e^(cN) (weighted by seeds, on log P):']
    out += ['  %s %s: %s' % (c, t['arena'], f.describe() if f else 'fewer than 3 sizes with P > 0: no fit')
            for c, f in sorted(fits.items())]
    if lacks:
        out += ['', 'Missing from the library (the commands that would measure it):']
        for what, cmd in lacks:
            out += ['- ' + what + ':', '  ' + cmd.replace('\n', '\n  ')]
    lengths = sorted({g['T'] for k, g in library.groups.items() if k[0] == t['arena'] and g.get('T')})
    if len(lengths) > 1:
        out.append('Note: the groups of %s come from runs of different lengths (%s ticks): their P are not alike; '
                   'give sweeps of one run length' % (t['arena'], ', '.join(map(str, lengths))))
    out += ['Note: ' + n for n in library.notes]
    return '\n'.join(out) + '\n'
