"""An experiment file (config/experiments/*.yaml) loaded and checked.

An experiment names an arena, controllers, swarm sizes, a number of runs (seeds 1 ... runs), a run
length and conditions (waveforms, or a measured series from a CSV file, each with a target: what V acts
on); `params` passes any other run_experiment parameter to every run. The robustness axes `noise` and
`population` (swarm_forage.robustness.axes) multiply the conditions. `model` (fordyca_2019, the default: FORDYCA
2019's code as it ran, or swarm_forage: its corrections, docs/FIDELITY.md) and `quirks` (single quirks added
on top) choose the model every run uses; a run of the default model without quirks has no model in its key. `models`
instead makes the model an axis like the conditions (the quirk set of each group: the ablation's rows,
docs/FIDELITY.md): a list of settings `MODEL`, `MODEL+QUIRK+...` or `MODEL+each` (one setting per quirk
the model lacks), or maps {model, quirks}.
Every key is checked: an unknown one, a size that is not a positive whole number, a waveform without
its parameters, a run listed twice, is an ExperimentError naming the key and what is valid. A condition's
values are checked by run_experiment itself (`--conditions`: the rule of a run's start-up), which also
gives its label."""
import os
import subprocess

import yaml

from swarm_forage.experiment import ExperimentError, kinds, models
from swarm_forage.robustness import axes as robustness_axes

KEYS = {
    'name': 'a name for the experiment (letters, digits, _ and -)',
    'description': 'free text',
    'arena': 'an arena of config/arenas (32x16, 64x32, 96x48) or a path to an arena YAML',
    'controllers': 'a list of controller kinds (`run_experiment --controllers` lists them)',
    'sizes': '{min: 1, max: N} (powers of two from min to max) or a list of swarm sizes',
    'runs': 'runs per group: seeds 1 ... runs (>= 1)',
    'ticks': 'ticks per run (>= 1; 5 ticks per simulated second)',
    'sample_interval': 'ticks per metrics sample (>= 1)',
    'conditions': 'a list of {waveform: ..., beta: number or list, alpha, frequency, phase, offset, target} '
                  'or {waveform: series, series: FILE.csv, target}',
    'params': 'a map of further run_experiment parameters, e.g. {serialize_block_ops: true}',
    'noise': robustness_axes.AXES['noise'],
    'population': robustness_axes.AXES['population'],
    'model': 'the model every run uses: fordyca_2019 (the default: FORDYCA 2019\'s code as it ran) or '
             'swarm_forage (its corrections, docs/FIDELITY.md); `run_experiment --models` lists the models and quirks',
    'quirks': 'a list of quirks added on top of the model (or one comma-separated string), e.g. '
              '[heading_estimate]; `run_experiment --models` lists them',
    'models': models.AXIS,
}
REQUIRED = ('name', 'arena', 'controllers', 'sizes', 'runs', 'ticks')
# A condition's parameters (run_experiment --help lists them), in the order a run's words give them: the
# record key hashes the words, so the order must not change (new ones go last).
CONDITION_KEYS = ('waveform', 'beta', 'alpha', 'frequency', 'phase', 'offset', 'target', 'series')
# run_experiment's own parameters; an experiment's `params` must not set them (the sweep does).
SET_BY_SWEEP = ('controller', 'arena', 'n_robots', 'seed', 'ticks') + CONDITION_KEYS + \
    ('bag', 'bag_dir', 'outcome', 'progress', 'model', 'quirks')


def _whole(value, key, low=1):
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise ExperimentError('%s must be a whole number >= %d (got %r)' % (key, low, value))
    return value


def _sizes(spec):
    if isinstance(spec, list):
        if not spec:
            raise ExperimentError('sizes must not be empty')
        sizes = [_whole(n, 'sizes[%d]' % k) for k, n in enumerate(spec)]
        twice = sorted({n for n in sizes if sizes.count(n) > 1})
        if twice:  # a size twice would run every one of its runs twice into one record
            raise ExperimentError('sizes lists %d more than once; list each size once' % twice[0])
        return sorted(sizes)
    if isinstance(spec, dict):
        unknown = set(spec) - {'min', 'max'}
        if unknown:
            raise ExperimentError('sizes: unknown key %s; valid keys: min, max' % sorted(unknown)[0])
        low, high = _whole(spec.get('min', 1), 'sizes.min'), _whole(spec.get('max'), 'sizes.max')
        if high < low:
            raise ExperimentError('sizes.max %d is below sizes.min %d' % (high, low))
        out, n = [], 1
        while n <= high:
            if n >= low:
                out.append(n)
            n *= 2
        if not out:
            raise ExperimentError('sizes {min: %d, max: %d} holds no power of two' % (low, high))
        return out
    raise ExperimentError('sizes must be %s (got %r)' % (KEYS['sizes'], spec))


def _series_condition(c, at, base):
    """A measured condition: its file (relative to the experiment file, or a file name of config/conditions,
    which run_experiment finds) and target; the file's rows are checked by run_experiment."""
    extra = sorted(set(c) - {'waveform', 'series', 'target'})
    if extra:
        raise ExperimentError('%s: waveform series takes no %s (V is the file\'s; valid keys: series, target)'
                              % (at, extra[0]))
    if not isinstance(c.get('series'), str) or not c['series']:
        raise ExperimentError('%s: waveform series needs series (a CSV file of rows t [s], V)' % at)
    path = c['series']
    if not os.path.isabs(path) and os.path.exists(os.path.join(base, path)):
        path = os.path.normpath(os.path.join(base, path))
    out = {'waveform': 'series', 'series': path}
    if 'target' in c:
        out['target'] = c['target']
    return out


def _conditions(spec, ticks, params, base='.'):
    """The conditions as run_experiment reads them: this checks only the experiment file's form (keys, beta
    lists, one condition once); their values are checked by run_experiment itself (_check_conditions)."""
    if spec is None:
        spec = [{'waveform': 'null'}]
    if not isinstance(spec, list) or not spec:
        raise ExperimentError('conditions must be %s' % KEYS['conditions'])
    out, where = [], []
    for k, c in enumerate(spec):
        at = 'conditions[%d]' % k
        if not isinstance(c, dict):
            raise ExperimentError('%s must be a map (%s)' % (at, KEYS['conditions']))
        unknown = sorted(set(c) - set(CONDITION_KEYS))
        if unknown:
            raise ExperimentError('%s: unknown key %s; valid keys: %s' % (at, unknown[0], ', '.join(CONDITION_KEYS)))
        for key in c:
            if any(ch in str(c[key]) for ch in '\t\n'):
                raise ExperimentError('%s.%s %r: a tab or line break cannot be passed on' % (at, key, c[key]))
        waveform = 'null' if c.get('waveform') is None else str(c['waveform'])
        if waveform == 'null':  # written one way only, so that it has one record key
            extra = sorted(set(c) - {'waveform'})
            if extra:
                raise ExperimentError('%s: waveform null takes no %s' % (at, extra[0]))
            out.append({'waveform': 'null'})
            where.append(at)
            continue
        if waveform == 'series':
            out.append(_series_condition(c, at, base))
            where.append(at)
            continue
        if 'series' in c:
            raise ExperimentError('%s: series is read by waveform series only (got waveform %s)' % (at, waveform))
        if 'beta' not in c:
            raise ExperimentError('%s: waveform %s needs beta (a number in [-1, 1] or a list of them)' % (at, waveform))
        fixed = {key: _value(c[key]) for key in CONDITION_KEYS[2:] if key in c}
        for beta in c['beta'] if isinstance(c['beta'], list) else [c['beta']]:
            out.append(dict(waveform=waveform, beta=_value(beta), **fixed))
            where.append(at)
    for c, tag in zip(out, _check_conditions(out, where, ticks, params)):
        c['label'] = tag
    # Equal conditions are one run under one key: refused rather than run twice into one record.
    seen = {}
    for c in out:
        words = tuple(sorted((k, v) for k, v in c.items() if k in CONDITION_KEYS))
        if words in seen:
            raise ExperimentError('conditions list %s twice (%s); list each condition once'
                                  % (c['label'], ', '.join('%s: %s' % kv for kv in words)))
        seen[words] = True
    return out


def _value(v):
    """A number as a float (its run_experiment word, hashed into the record key, has always been the
    float's); anything else as given, for run_experiment to refuse by name."""
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v


def _check_conditions(conditions, where, ticks, params):
    """Each condition checked by run_experiment with the rule of a run's start-up, all in one call
    (`run_experiment --conditions`); returns each one's tag (its label in record keys, e.g. step_down0.4)."""
    run = [run_word('ticks', ticks)] + [run_word(k, params[k]) for k in ('ticks_per_second',) if k in params]
    lines = ''.join('\t'.join(run_word(k, c[k]) for k in CONDITION_KEYS if k in c) + '\n' for c in conditions)
    try:
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--conditions'] + run, input=lines,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    except OSError as err:
        raise ExperimentError('cannot check the conditions: rosrun: %s (source the workspace setup.bash)'
                              % err.strerror)
    verdicts = [line.split('\t', 1) for line in proc.stdout.splitlines()]
    if len(verdicts) != len(conditions) or any(len(v) != 2 for v in verdicts):
        raise ExperimentError('cannot check the conditions with run_experiment --conditions: %s'
                              % (proc.stderr.strip() or proc.stdout.strip() or 'exit code %d' % proc.returncode))
    for at, (verdict, text) in zip(where, verdicts):
        if verdict != 'ok':
            raise ExperimentError('%s: %s' % (at, text))
    return [text for _, text in verdicts]


def load(path, overrides=None):
    """The experiment of `path`, validated; `overrides` (runs, ticks, sizes, max_size, controllers, model,
    quirks, models: a models axis; noise: the levels, population: the multipliers of the robustness axes) replace
    its values as the command line asks."""
    spec = _read(path)
    o = overrides or {}
    name = str(spec['name'])
    if not name or any(not (ch.isalnum() or ch in '_-') for ch in name):
        raise ExperimentError('name %r: %s' % (name, KEYS['name']))
    controllers = _controllers(o.get('controllers') or spec['controllers'])
    sizes = _sizes(o['sizes'] if o.get('sizes') else spec['sizes'])
    if o.get('max_size'):
        kept = [n for n in sizes if n <= o['max_size']]
        if not kept:
            raise ExperimentError('--max-size %d is below every swarm size (%s); valid: --max-size >= %d'
                                  % (o['max_size'], ', '.join(map(str, sizes)), sizes[0]))
        sizes = kept
    params = _params(spec.get('params') or {})
    ticks = _whole(o.get('ticks') or spec['ticks'], 'ticks')
    axes = {}
    try:
        for axis in robustness_axes.AXES:
            robustness_axes.check_params(axis, axis in spec, params)
            axes[axis] = robustness_axes.settings(axis, spec.get(axis), o.get(axis))
    except robustness_axes.VariationError as err:
        raise ExperimentError(str(err))
    settings = _model_settings(path, spec, o)
    arena = str(spec['arena'])
    if any(ch in arena for ch in '\t\n'):
        raise ExperimentError('arena %r: a name or path with a tab or line break cannot be passed on' % arena)
    if (os.sep in arena or arena.endswith('.yaml')) and not os.path.isabs(arena):  # relative to the experiment
        arena = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), arena))
    return {
        'name': name,
        'description': str(spec.get('description', '')),
        'arena': arena,
        'controllers': list(dict.fromkeys(controllers)),
        'sizes': sizes,
        'runs': _whole(o.get('runs') or spec['runs'], 'runs'),
        'ticks': ticks,
        'sample_interval': _whole(spec.get('sample_interval', 1000), 'sample_interval'),
        'conditions': _conditions(spec.get('conditions'), ticks, params, os.path.dirname(os.path.abspath(path))),
        'params': params,
        'noise': axes['noise'],
        'population': axes['population'],
        'models': settings,
    }


def _read(path):
    """The file's map: YAML, only known keys, the required ones there."""
    try:
        with open(path) as f:
            spec = yaml.safe_load(f)
    except OSError as err:
        raise ExperimentError('cannot read %s: %s' % (path, err.strerror))
    except yaml.YAMLError as err:
        raise ExperimentError('%s is not valid YAML: %s' % (path, err))
    if not isinstance(spec, dict):
        raise ExperimentError('%s must be a map of %s' % (path, ', '.join(KEYS)))
    unknown = sorted(set(spec) - set(KEYS))
    if unknown:
        raise ExperimentError('%s: unknown key %s; valid keys: %s' % (path, unknown[0], ', '.join(KEYS)))
    missing = [k for k in REQUIRED if k not in spec]
    if missing:
        raise ExperimentError('%s: %s is missing (%s)' % (path, missing[0], KEYS[missing[0]]))
    return spec


def _controllers(controllers):
    known = kinds.controller_names()
    if not isinstance(controllers, list) or not controllers or any(c not in known for c in controllers):
        raise ExperimentError('controllers must be a list of %s (got %r)' % (', '.join(known), controllers))
    twice = [c for k, c in enumerate(controllers) if c in controllers[:k]]
    if twice:
        raise ExperimentError('controllers lists %s more than once; list each controller once' % twice[0])
    return controllers


def _params(params):
    if not isinstance(params, dict):
        raise ExperimentError('params must be %s' % KEYS['params'])
    for key in params:
        if key in SET_BY_SWEEP:
            raise ExperimentError('params.%s is set by the sweep itself; use the experiment keys instead' % key)
        if any(ch in str(key) + str(params[key]) for ch in '\t\n'):
            raise ExperimentError('params.%s: a name or value with a tab or line break cannot be passed on' % key)
    return params


def _model_settings(path, spec, o):
    """The settings of the models axis: the file's model and quirks (one setting), or its models axis, or the
    command line's in place of either."""
    if 'models' in spec and ('model' in spec or 'quirks' in spec):
        raise ExperimentError('%s: models (the model as an axis) goes without model and quirks: give the settings '
                              'there, e.g. [fordyca_2019+heading_estimate]' % path)
    if o.get('models') and (o.get('model') or o.get('quirks') is not None):
        raise ExperimentError('--models goes without --model and --quirks: give the settings there, e.g. '
                              '--models fordyca_2019+heading_estimate')
    if o.get('models'):
        return models.model_settings(o['models'], '--models')
    if 'models' in spec and not (o.get('model') or o.get('quirks') is not None):
        return models.model_settings(spec['models'])
    if 'models' in spec:
        raise ExperimentError('%s has a models axis: replace it with --models (e.g. --models %s), not --model or '
                              '--quirks' % (path, 'fordyca_2019'))
    return [models.setting(*models.model_choice(o.get('model') or spec.get('model'),
                                                o.get('quirks') if o.get('quirks') is not None else spec.get('quirks'),
                                                '--model' if o.get('model') else 'model',
                                                '--quirks' if o.get('quirks') is not None else 'quirks'))]


def run_word(key, value):
    if isinstance(value, bool):
        value = 'true' if value else 'false'
    return '%s:=%s' % (key, value)
