"""An experiment file's robustness axes (docs/robustness-study.md): `noise` (sensor and actuator noise)
and `population` (population dynamics), each a list of settings whose product with the conditions
gives the runs.

A setting is a map of world_node parameters without their prefix: `noise` settings take
`<device>/model` and `<device>/level` (device: proximity, light, ground, position, heading, wheels or
all), `population` settings take `death`, `birth`, `malfunction`, `repair`, `max_size` and
`multiplier` (a number every rate is multiplied by, so that one base gives the study's x1, 2, 4, 8).
A value may be a list: the setting stands for every combination. A setting without noise (every level
0) or without population dynamics (every rate 0) gives no words at all: it is the plain run, the
reference of the robustness measures, with the record key of the same run of an experiment without
these axes. The values themselves are checked by run_experiment (the rule of a run's start-up)."""
import itertools


AXES = {
    'noise': 'a list of noise settings, e.g. [{}, {all/model: gaussian, all/level: [0.01, 0.02]}] (keys: '
             '<device>/model, <device>/level; device: proximity, light, ground, position, heading, wheels, all)',
    'population': 'a list of population settings, e.g. [{}, {death: 1e-4, malfunction: 1e-3, repair: 4e-3, '
                  'multiplier: [1, 2, 4, 8]}] (keys: death, birth, malfunction, repair, max_size, multiplier)',
}
DEVICES = ('all', 'proximity', 'light', 'ground', 'position', 'heading', 'wheels')
RATES = ('death', 'birth', 'malfunction', 'repair')
POPULATION_KEYS = RATES + ('max_size', 'multiplier')
# A setting's label in record keys: short names of what it sets.
SHORT = {'death': 'd', 'birth': 'b', 'malfunction': 'm', 'repair': 'r', 'max_size': 'max'}


class VariationError(ValueError):
    pass


def _number(value, at):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise VariationError('%s must be a number (got %r)' % (at, value))
    return float(value)


def _text(value):
    """A number as its run_experiment word: 12 significant digits, so that 1e-4 x 3 reads 0.0003."""
    return '%.12g' % value if isinstance(value, float) else str(value)


def _combinations(setting, at):
    """Every combination of a setting's list values, as maps of scalar values (keys in the file's order)."""
    keys = list(setting)
    choices = []
    for key in keys:
        value = setting[key]
        values = value if isinstance(value, list) else [value]
        if not values:
            raise VariationError('%s.%s: an empty list' % (at, key))
        for v in values:
            if isinstance(v, (list, dict)) or v is None or any(ch in str(v) for ch in '\t\n '):
                raise VariationError('%s.%s: %r is not a number or a word' % (at, key, v))
        choices.append(values)
    return [dict(zip(keys, combo)) for combo in itertools.product(*choices)]


def _noise_words(s, at):
    for key in s:
        device, _, field = key.partition('/')
        if device not in DEVICES or field not in ('model', 'level') or (device == 'ground' and field == 'model'):
            raise VariationError('%s: unknown key %s; valid keys: <device>/model, <device>/level for device in %s '
                                 '(ground has no model: its level is a misread probability)'
                                 % (at, key, ', '.join(DEVICES)))
    levels = {k: _number(v, '%s.%s' % (at, k)) for k, v in s.items() if k.endswith('/level')}
    if not any(levels.values()):
        return [], ''
    words = [('noise/' + k, _text(levels.get(k, v))) for k, v in s.items()]
    label = 'saa-' + '-'.join('%s%s%s' % (k.split('/')[0], '-' + str(s[k.split('/')[0] + '/model'])
                                          if k.split('/')[0] + '/model' in s else '', _text(v))
                              for k, v in levels.items())
    return words, label


def _population_words(s, at):
    unknown = sorted(set(s) - set(POPULATION_KEYS))
    if unknown:
        raise VariationError('%s: unknown key %s; valid keys: %s' % (at, unknown[0], ', '.join(POPULATION_KEYS)))
    multiplier = _number(s.get('multiplier', 1.0), at + '.multiplier')
    if multiplier <= 0:
        raise VariationError('%s.multiplier must be > 0 (got %s)' % (at, _text(multiplier)))
    rates = {k: _number(s[k], '%s.%s' % (at, k)) * multiplier for k in RATES if k in s}
    if not any(rates.values()):
        return [], ''
    # The PD measure needs a steady state: refused here rather than swept into "no steady state" rows. Death
    # only (no birth) has the authors' value (T) under definitions:=authors_code, so it is kept.
    lam = rates.get('death', 0.0) + rates.get('malfunction', 0.0)
    mu = rates.get('birth', 0.0) + rates.get('repair', 0.0)
    if not lam < mu and not (rates.get('death', 0.0) > 0 and not rates.get('birth', 0.0)):
        raise VariationError('%s: no steady state: lambda = death + malfunction = %g >= mu = birth + repair = %g '
                             'per tick; the PD robustness needs death + malfunction < birth + repair (or death '
                             'only)' % (at, lam, mu))
    words = [('population/' + k, _text(rates[k])) for k in RATES if k in rates]
    if 'max_size' in s:
        words.append(('population/max_size', _text(s['max_size'])))
    label = 'pd-' + '-'.join('%s%s' % (SHORT[k], _text(v)) for k, v in rates.items() if v) + \
        ('-max%s' % s['max_size'] if 'max_size' in s else '')
    return words, label


def _overridden(axis, setting, override):
    """`setting` with its swept lists (noise: every <device>/level list; population: the multiplier list)
    replaced by `override` (sweep --noise-levels, --multipliers)."""
    if override is None:
        return setting
    swept = (lambda k: k.endswith('/level')) if axis == 'noise' else (lambda k: k == 'multiplier')
    return {k: list(override) if swept(k) and isinstance(v, list) else v for k, v in setting.items()}


def settings(axis, spec, override=None):
    """The settings of axis `axis` ('noise' or 'population') as dicts {words: [(name, value)], label}; `spec`
    as the experiment file gives it (None: the axis is absent, one plain setting); `override` replaces the
    swept lists (see _overridden). Raises VariationError."""
    swept = {'noise': '--noise-levels: no noise setting has a list of levels',
             'population': '--multipliers: no population setting has a list of multipliers'}[axis]
    if spec is None:
        if override is not None:
            raise VariationError('%s (the experiment has no %s axis)' % (swept, axis))
        return [{'words': [], 'label': ''}]
    if not isinstance(spec, list) or not spec:
        raise VariationError('%s must be %s' % (axis, AXES[axis]))
    if override is not None and all(_overridden(axis, s, override) == s for s in spec if isinstance(s, dict)):
        raise VariationError(swept + ' to replace')
    out, seen = [], {}
    for k, setting in enumerate(spec):
        at = '%s[%d]' % (axis, k)
        if not isinstance(setting, dict):
            raise VariationError('%s must be a map (%s)' % (at, AXES[axis]))
        for combo in _combinations(_overridden(axis, setting, override), at):
            words, label = (_noise_words if axis == 'noise' else _population_words)(combo, at)
            if tuple(words) in seen:  # one run under one key: refused rather than run twice into one record
                raise VariationError('%s gives %s, as %s already does; list each setting once'
                                     % (at, label or 'the plain run (no %s)' % axis, seen[tuple(words)]))
            seen[tuple(words)] = at
            out.append({'words': words, 'label': label})
    return out


def check_params(axis, present, params):
    """An axis and `params` must not both set the axis' parameters (the sweep would pass them twice)."""
    if present:
        for key in params:
            if str(key).startswith(axis + '/'):
                raise VariationError('params.%s: the experiment has a %s axis; give %s settings there'
                                     % (key, axis, axis))
