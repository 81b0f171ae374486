"""`recommend`'s text: the ranked table, the top choice's reasons, what the library lacks (with the sweep
commands that would measure it) and the notes."""
import os

from swarm_forage.recommend import library as lib
from swarm_forage.recommend import target
from swarm_forage.recommend.rank import CRITERIA, NORMALISATION


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
