"""The candidates of a target, (controller, N) measured or fitted, each with its criteria, and their score:
every criterion normalised by min-max across the candidates, then weighted as the target asks."""
import math

from swarm_forage.recommend import model

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
