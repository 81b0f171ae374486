"""A target of `recommend` (config/targets/*.yaml): what it may say, read and checked in full before anything
is computed (docs/recommend.md). A fault is a TargetError naming the key and what is valid; `recommend`
exits 2 on it."""
import math
import os
import subprocess

import yaml

CRITERIA = ('performance', 'scalability', 'self_organization', 'reactivity', 'adaptability', 'robustness')
KEYS = {
    'name': 'free text',
    'description': 'free text',
    'arena': 'a name of config/arenas/*.yaml (32x16, 64x32, 96x48)',
    'area': 'the operating area [m^2] (instead of arena): the smallest arena of config/arenas at least this large',
    'aspect': 'with area: width / height of the arena (default 2, the arenas of config/arenas)',
    'robots': 'the robots available: candidates have N <= robots (a whole number >= 1)',
    'conditions': 'ideal, or {waveform: step_up|step_down|..., beta: number}, or {waveform: series, series: '
                  'FILE.csv}, or a list of these (R and A are averaged over them)',
    'weights': 'a map of non-negative numbers, not all zero, over: ' + ', '.join(CRITERIA),
    'noise': 'the noise level expected (SAA robustness; needs a robustness_saa sweep)',
    'population': 'the rate multiplier of robots failing expected (PD robustness; needs a robustness_pd sweep)',
}


class TargetError(ValueError):
    pass


def arenas():
    """{name: (width, height)} of the arenas ~arena names (config/arenas/*.yaml), as run_experiment finds and
    reads them (`run_experiment --arenas`: the one lookup of an arena by name)."""
    try:
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--arenas'], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)
    except OSError as err:
        raise TargetError('cannot list the arenas: rosrun: %s (source the workspace setup.bash)' % err.strerror)
    listing = yaml.safe_load(proc.stdout) if proc.returncode == 0 else None
    if not isinstance(listing, list):
        raise TargetError('`run_experiment --arenas` did not list the arenas (exit %d): %s'
                          % (proc.returncode, (proc.stdout + proc.stderr).strip()))
    return {a['name']: (float(a['width']), float(a['height'])) for a in listing}


def _number(value, where, low=None):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise TargetError('%s must be a number (got %r)' % (where, value))
    if low is not None and value < low:
        raise TargetError('%s must be >= %g (got %r)' % (where, low, value))
    return float(value)


def _conditions(spec):
    """[(waveform, beta)] of the target's conditions; ('null', 0.0) is ideal; a series is ('series', path)."""
    spec = 'ideal' if spec is None else spec
    items = spec if isinstance(spec, list) else [spec]
    if not items:
        raise TargetError('conditions: an empty list; valid: %s' % KEYS['conditions'])
    out = []
    for k, c in enumerate(items):
        at = 'conditions' + ('[%d]' % k if isinstance(spec, list) else '')
        if c in ('ideal', 'null') or c == {'waveform': 'null'}:
            out.append(('null', 0.0))
            continue
        if not isinstance(c, dict) or not isinstance(c.get('waveform'), str):
            raise TargetError('%s: %r is not a condition; valid: %s' % (at, c, KEYS['conditions']))
        if c['waveform'] == 'series':
            extra = sorted(set(c) - {'waveform', 'series'})
            if extra or not isinstance(c.get('series'), str):
                raise TargetError('%s: waveform series takes series: FILE.csv only (got %s)' % (at, sorted(c)))
            out.append(('series', c['series']))
            continue
        extra = sorted(set(c) - {'waveform', 'beta'})
        if extra:
            raise TargetError('%s: unknown key %s; valid: waveform, beta (alpha is the sweep\'s: T/2)' % (at, extra[0]))
        if 'beta' not in c:
            raise TargetError('%s: waveform %s needs beta (a number in [-1, 1])' % (at, c['waveform']))
        out.append((c['waveform'], _number(c['beta'], at + '.beta', -1.0)))
    return out


def load(path):
    """The checked target: dict with name, arena, area, robots, conditions [(waveform, beta)], weights
    {criterion: w} (every criterion, 0 when not given), noise, population."""
    try:
        with open(path) as f:
            raw = yaml.safe_load(f)
    except OSError as err:
        raise TargetError('cannot read %s: %s' % (path, err.strerror))
    except yaml.YAMLError as err:
        raise TargetError('%s is not YAML: %s' % (path, str(err).replace('\n', ' ')))
    if not isinstance(raw, dict):
        raise TargetError('%s: a target is a map of keys; valid: %s' % (path, ', '.join(KEYS)))
    known = arenas()
    unknown = sorted(set(raw) - set(KEYS))
    if unknown:
        raise TargetError('unknown key %r; valid keys: %s' % (unknown[0], ', '.join(KEYS)))
    t = {'name': str(raw.get('name', os.path.basename(path))), 'noise': None, 'population': None}
    if 'arena' in raw:
        if 'area' in raw or 'aspect' in raw:
            raise TargetError('give arena or area (and aspect), not both')
        if raw['arena'] not in known:
            raise TargetError('arena %r is not in config/arenas; valid: %s (or give area and aspect)'
                              % (raw['arena'], ', '.join(known)))
        t['arena'] = raw['arena']
    elif 'area' in raw:
        area = _number(raw['area'], 'area', 1e-9)
        aspect = _number(raw.get('aspect', 2.0), 'aspect', 1e-9)
        fits = sorted((w * h, n) for n, (w, h) in known.items() if w * h >= area and abs(w / h - aspect) < 0.05 * aspect)
        if not fits:
            raise TargetError('no arena of config/arenas has area >= %g m^2 and aspect %g; valid: %s' % (
                area, aspect, ', '.join('%s (%g m^2, aspect %g)' % (n, w * h, w / h) for n, (w, h) in known.items())))
        t['arena'] = fits[0][1]
    else:
        raise TargetError('the target needs arena (%s) or area [m^2]' % ', '.join(known))
    t['area'] = known[t['arena']][0] * known[t['arena']][1]
    robots = raw.get('robots')
    if isinstance(robots, bool) or not isinstance(robots, int) or robots < 1:
        raise TargetError('robots must be a whole number >= 1 (the robots available; got %r)' % (robots,))
    t['robots'] = robots
    t['conditions'] = _conditions(raw.get('conditions'))
    weights = raw.get('weights')
    if not isinstance(weights, dict) or not weights:
        raise TargetError('weights must be a map over %s (got %r)' % (', '.join(CRITERIA), weights))
    for k, w in weights.items():
        if k not in CRITERIA:
            raise TargetError('weights: unknown criterion %r; valid: %s' % (k, ', '.join(CRITERIA)))
        if _number(w, 'weights.' + k) < 0:
            raise TargetError('weights.%s is negative (%g); weights must be >= 0' % (k, w))
    t['weights'] = {k: float(weights.get(k, 0.0)) for k in CRITERIA}
    if not any(t['weights'].values()):
        raise TargetError('weights are all zero; give at least one of %s a positive weight' % ', '.join(CRITERIA))
    if 'noise' in raw:
        t['noise'] = _number(raw['noise'], 'noise', 0.0)
    if 'population' in raw:
        t['population'] = _number(raw['population'], 'population', 0.0)
    if t['weights']['robustness'] > 0 and t['noise'] is None and t['population'] is None:
        raise TargetError('weights.robustness needs noise (a level) or population (a rate multiplier) to measure it at')
    return t


def describe(t):
    cond = ', '.join('ideal' if w == 'null' else ('series %s' % b if w == 'series' else '%s beta %g' % (w, b))
                     for w, b in t['conditions'])
    return '%s: arena %s (%.0f m^2), up to %d robots, conditions %s%s%s' % (
        t['name'], t['arena'], t['area'], t['robots'], cond,
        '' if t['noise'] is None else ', noise %g' % t['noise'],
        '' if t['population'] is None else ', population x%g' % t['population'])
