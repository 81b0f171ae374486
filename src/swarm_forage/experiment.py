"""Experiment files (config/experiments/*.yaml): loading, validation and expansion into runs.

An experiment names an arena, controllers, swarm sizes, a number of runs (seeds 1 ... runs), a run
length and conditions (waveforms, or a measured series from a CSV file, each with a target: what V acts
on); `params` passes any other run_experiment parameter to every run. The robustness axes `noise` and
`population` (robustness_axes.py) multiply the conditions. `model` (fordyca_2019, the default: FORDYCA
2019's code as it ran, or swarm_forage: its corrections, docs/FIDELITY.md) and `quirks` (single quirks added
on top) choose the model every run uses; a run of the default model without quirks has no model in its key. `models`
instead makes the model an axis like the conditions (the quirk set of each group: the ablation's rows,
docs/FIDELITY.md): a list of settings `MODEL`, `MODEL+QUIRK+...` or `MODEL+each` (one setting per quirk
the model lacks), or maps {model, quirks}.
Every key is checked: an unknown one, a size that is not a positive whole number, a waveform without
its parameters, a run listed twice, is an ExperimentError naming the key and what is valid. A condition's
values are checked by run_experiment itself (`--conditions`: the rule of a run's start-up), which also
gives its label.

A run's key is its record's file stem as the core names it (`run_experiment --identity`: runBagName, whose
last part is the run identity). The identity is computed by the core from everything that changes a run's
outcome, files by content (the arena's values, a series' digest, the constants), never by path, so an
edited input gives other keys and no record of the old inputs is taken for one of the new."""
import functools
import os
import subprocess

import rospkg
import yaml

from swarm_forage import robustness_axes

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
    'models': 'the model as an axis: a list of settings, each MODEL, MODEL+QUIRK[+QUIRK ...] or MODEL+each (one '
              'setting per quirk the model lacks, alone), or a map {model: MODEL, quirks: [QUIRK, ...] or each}; '
              'e.g. [swarm_forage, fordyca_2019, swarm_forage+each]',
}
PACKAGE = rospkg.RosPack().get_path('swarm_forage')
REQUIRED = ('name', 'arena', 'controllers', 'sizes', 'runs', 'ticks')
# A condition's parameters (run_experiment --help lists them), in the order a run's words give them: the
# record key hashes the words, so the order must not change (new ones go last).
CONDITION_KEYS = ('waveform', 'beta', 'alpha', 'frequency', 'phase', 'offset', 'target', 'series')
# run_experiment's own parameters; an experiment's `params` must not set them (the sweep does).
SET_BY_SWEEP = ('controller', 'arena', 'n_robots', 'seed', 'ticks') + CONDITION_KEYS + \
    ('bag', 'bag_dir', 'outcome', 'progress', 'model', 'quirks')


class ExperimentError(ValueError):
    pass


@functools.lru_cache(maxsize=None)
def controller_kinds():
    """The controller kinds of this build, from its registry (`run_experiment --controllers`): the built-in
    ones and every plugin found, as dicts with name, display_name, colour, constants (the YAML sections it
    reads), line_of_sight, static_cache, package, plugin (true for a plugin) and defaults (its YAML file)."""
    # stderr apart: a plugin that fails to load is reported there and left out of the listing.
    proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--controllers'], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, universal_newlines=True)
    kinds = yaml.safe_load(proc.stdout) if proc.returncode == 0 else None
    if not isinstance(kinds, list) or not kinds:
        raise ExperimentError('`run_experiment --controllers` did not list the controller kinds (exit %d): %s'
                              % (proc.returncode, (proc.stdout + proc.stderr).strip()))
    return tuple(kinds)


@functools.lru_cache(maxsize=None)
def models():
    """The models and quirks of this build (`run_experiment --models`): a dict with default (the default
    model's name), models (the names) and quirks (dicts with name, side, fordyca_2019 and what)."""
    try:
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--models'], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)
    except OSError as err:
        raise ExperimentError('cannot list the models: rosrun: %s (source the workspace setup.bash)' % err.strerror)
    listing = yaml.safe_load(proc.stdout) if proc.returncode == 0 else None
    if not isinstance(listing, dict) or not listing.get('models') or 'quirks' not in listing:
        raise ExperimentError('`run_experiment --models` did not list the models (exit %d): %s'
                              % (proc.returncode, (proc.stdout + proc.stderr).strip()))
    return listing


def model_choice(model, quirks, where='model', where_quirks='quirks'):
    """(model, [quirk names]) checked against this build's names; `quirks` is a list or a comma-separated
    string (None: none). An unknown name is an ExperimentError naming the valid ones."""
    listing = models()
    model = listing['default'] if model is None else model
    if not isinstance(model, str) or model not in listing['models']:
        raise ExperimentError('%s %r is unknown; valid: %s (%s is the default)'
                              % (where, model, ', '.join(listing['models']), listing['default']))
    names = [q['name'] for q in listing['quirks']]
    if quirks is None:
        quirks = []
    if isinstance(quirks, str):
        quirks = [q.strip() for q in quirks.split(',') if q.strip()]
    if not isinstance(quirks, list) or any(not isinstance(q, str) for q in quirks):
        raise ExperimentError('%s must be a list of quirk names (or one comma-separated string); valid: %s'
                              % (where_quirks, ', '.join(names)))
    for q in quirks:
        if q not in names:
            raise ExperimentError('%s: %r is not a quirk; valid: %s' % (where_quirks, q, ', '.join(names)))
    twice = [q for k, q in enumerate(quirks) if q in quirks[:k]]
    if twice:
        raise ExperimentError('%s lists %s more than once; list each quirk once' % (where_quirks, twice[0]))
    return model, [q for q in names if q in quirks]  # in the listing's order: one set, one key


def model_words(model, quirks):
    """The run_experiment words of a model choice: none for the default model without quirks."""
    words = [] if model == models()['default'] else [('model', model)]
    return words + ([('quirks', ','.join(quirks))] if quirks else [])


def model_label(model, quirks):
    """The model choice in record keys and folder names: '' for the default model without quirks."""
    return '_'.join(([] if model == models()['default'] else [model]) + list(quirks))


def model_quirks(model):
    """The quirks `model` has by itself (fordyca_2019: those the listing marks; another model: none)."""
    return {q['name'] for q in models()['quirks'] if q['fordyca_2019']} if model == 'fordyca_2019' else set()


def model_name(quirks):
    """A set of quirks (a record's, read from its identity words) as the setting that gives it, whatever the
    default model: 'fordyca_2019' or 'swarm_forage', with '+QUIRK' for each quirk added on top."""
    order = [q['name'] for q in models()['quirks']]
    quirks = set(quirks)
    fordyca = model_quirks('fordyca_2019')
    model, extra = ('fordyca_2019', quirks - fordyca) if quirks >= fordyca else ('swarm_forage', quirks)
    return '+'.join([model] + [q for q in order if q in extra] + sorted(extra - set(order)))


def _setting(model, quirks):
    """One setting of the models axis: its run_experiment words, its label in record keys and group names ('' for
    the default model without quirks) and its name (MODEL[+QUIRK ...], the same whatever the default)."""
    return {'model': model, 'quirks': list(quirks), 'words': model_words(model, quirks),
            'label': model_label(model, quirks), 'name': '+'.join([model] + list(quirks))}


def model_settings(spec, where='models'):
    """The settings of a models axis as experiment files and `sweep --models` give it (a list of `MODEL`,
    `MODEL+QUIRK+...`, `MODEL+each` or {model, quirks} entries; a string is split at commas). A quirk the
    model already has, a setting twice (also two that give the same quirks) or an empty list is an
    ExperimentError."""
    if isinstance(spec, str):
        spec = [s.strip() for s in spec.split(',') if s.strip()]
    if not isinstance(spec, list) or not spec:
        raise ExperimentError('%s must be %s' % (where, KEYS['models']))
    names = [q['name'] for q in models()['quirks']]
    out, seen = [], {}
    for k, entry in enumerate(spec):
        at = '%s[%d]' % (where, k)
        if isinstance(entry, str):
            model, _, rest = entry.partition('+')
            quirks = [q for q in rest.split('+') if q] if rest else []
        elif isinstance(entry, dict):
            unknown = sorted(set(entry) - {'model', 'quirks'})
            if unknown or 'model' not in entry:
                raise ExperimentError('%s: %s; valid keys: model (required), quirks'
                                      % (at, 'unknown key %s' % unknown[0] if unknown else 'model is missing'))
            model, quirks = entry['model'], entry.get('quirks')
        else:
            raise ExperimentError('%s must be a string MODEL[+QUIRK ...] or a map {model, quirks} (got %r)'
                                  % (at, entry))
        each = quirks == 'each' or quirks == ['each']
        model, quirks = model_choice(model, None if each else quirks, at + ' model', at + ' quirks')
        has = model_quirks(model)
        already = [q for q in quirks if q in has]
        if already:
            raise ExperimentError('%s: %s already has %s; list a quirk on top of a model only when the model lacks '
                                  'it' % (at, model, already[0]))
        for chosen in ([[q] for q in names if q not in has] if each else [quirks]):
            effective = frozenset(has | set(chosen))
            name = '+'.join([model] + chosen)
            if effective in seen:  # one run under one key: refused rather than run twice into one record
                raise ExperimentError('%s gives %s, the same quirks as %s already gives; list each setting once'
                                      % (at, name, seen[effective]))
            seen[effective] = name
            out.append(_setting(model, chosen))
    if not out:
        raise ExperimentError('%s gives no setting (each quirk is already in its model)' % where)
    return out


def controller_names():
    return tuple(k['name'] for k in controller_kinds())


def controller_kind(name):
    """The listing's entry of kind `name` (a plugin's <package>/<Class>); a stand-in for a kind this build
    lacks (an old record's), so that tables and figures of it still draw."""
    for k in controller_kinds():
        if k['name'] == name:
            return k
    return {'name': name, 'display_name': name, 'colour': 'tab:gray', 'constants': [name], 'plugin': '/' in name}


def display_name(name):
    """A controller's display name, built-in or plugin (run_experiment --controllers): the label of tables
    and figures."""
    return controller_kind(name)['display_name']


def file_safe(name):
    """A name fit for a group label or a folder: a plugin's '/' becomes '_'."""
    return ''.join(ch if ch.isalnum() or ch in '.-_' else '_' for ch in name)


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
    run = [_word('ticks', ticks)] + [_word(k, params[k]) for k in ('ticks_per_second',) if k in params]
    lines = ''.join('\t'.join(_word(k, c[k]) for k in CONDITION_KEYS if k in c) + '\n' for c in conditions)
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
    o = overrides or {}
    name = str(spec['name'])
    if not name or any(not (ch.isalnum() or ch in '_-') for ch in name):
        raise ExperimentError('name %r: %s' % (name, KEYS['name']))
    controllers = o.get('controllers') or spec['controllers']
    known = controller_names()
    if not isinstance(controllers, list) or not controllers or any(c not in known for c in controllers):
        raise ExperimentError('controllers must be a list of %s (got %r)' % (', '.join(known), controllers))
    twice = [c for k, c in enumerate(controllers) if c in controllers[:k]]
    if twice:
        raise ExperimentError('controllers lists %s more than once; list each controller once' % twice[0])
    sizes = _sizes(o['sizes'] if o.get('sizes') else spec['sizes'])
    if o.get('max_size'):
        kept = [n for n in sizes if n <= o['max_size']]
        if not kept:
            raise ExperimentError('--max-size %d is below every swarm size (%s); valid: --max-size >= %d'
                                  % (o['max_size'], ', '.join(map(str, sizes)), sizes[0]))
        sizes = kept
    params = spec.get('params') or {}
    if not isinstance(params, dict):
        raise ExperimentError('params must be %s' % KEYS['params'])
    for key in params:
        if key in SET_BY_SWEEP:
            raise ExperimentError('params.%s is set by the sweep itself; use the experiment keys instead' % key)
        if any(ch in str(key) + str(params[key]) for ch in '\t\n'):
            raise ExperimentError('params.%s: a name or value with a tab or line break cannot be passed on' % key)
    ticks = _whole(o.get('ticks') or spec['ticks'], 'ticks')
    axes = {}
    try:
        for axis in robustness_axes.AXES:
            robustness_axes.check_params(axis, axis in spec, params)
            axes[axis] = robustness_axes.settings(axis, spec.get(axis), o.get(axis))
    except robustness_axes.VariationError as err:
        raise ExperimentError(str(err))
    if 'models' in spec and ('model' in spec or 'quirks' in spec):
        raise ExperimentError('%s: models (the model as an axis) goes without model and quirks: give the settings '
                              'there, e.g. [fordyca_2019+heading_estimate]' % path)
    if o.get('models') and (o.get('model') or o.get('quirks') is not None):
        raise ExperimentError('--models goes without --model and --quirks: give the settings there, e.g. '
                              '--models fordyca_2019+heading_estimate')
    if o.get('models'):
        settings = model_settings(o['models'], '--models')
    elif 'models' in spec and not (o.get('model') or o.get('quirks') is not None):
        settings = model_settings(spec['models'])
    elif 'models' in spec:
        raise ExperimentError('%s has a models axis: replace it with --models (e.g. --models %s), not --model or '
                              '--quirks' % (path, 'fordyca_2019'))
    else:
        settings = [_setting(*model_choice(o.get('model') or spec.get('model'),
                                           o.get('quirks') if o.get('quirks') is not None else spec.get('quirks'),
                                           '--model' if o.get('model') else 'model',
                                           '--quirks' if o.get('quirks') is not None else 'quirks'))]
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


def _word(key, value):
    if isinstance(value, bool):
        value = 'true' if value else 'false'
    return '%s:=%s' % (key, value)


def expand(exp, group_runs=None):
    """One dict per run: key (file stem), args (run_experiment words), robot_ticks, and its group (group: the
    key without seed and hash). Seeds 1 ... runs per group: `group_runs` {group: runs} (sweep_rounds, a
    group-runs file) gives some groups theirs, the others have exp['runs']; a name that is no group of the
    experiment is an ExperimentError."""
    runs, group_runs, groups = [], group_runs or {}, []
    for controller in exp['controllers']:
        for n in exp['sizes']:
            for c in exp['conditions']:
                for noise in exp.get('noise') or [{'words': [], 'label': ''}]:
                    for pd in exp.get('population') or [{'words': [], 'label': ''}]:
                        for m in exp['models']:
                            group = _run(exp, controller, n, c, noise, pd, m, 1)['group']
                            groups.append(group)
                            for seed in range(1, group_runs.get(group, exp['runs']) + 1):
                                runs.append(_run(exp, controller, n, c, noise, pd, m, seed))
    unknown = sorted(set(group_runs) - set(groups))
    if unknown:
        raise ExperimentError('group %s is not a group of %s (%d groups, e.g. %s)'
                              % (unknown[0], exp['name'], len(groups), ', '.join(groups[:3])))
    for r, (identity, name) in zip(runs, identities([r['args'] for r in runs])):
        r['identity'], r['key'] = identity, name[:-len('.bag')]
    return runs


def identities(args):
    """[(identity, bag name)] of each run's run_experiment words, as the core computes them
    (`run_experiment --identity`, one call for them all); a run it would refuse is an ExperimentError."""
    if not args:
        return []
    try:
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--identity'],
                              input=''.join('\t'.join(a) + '\n' for a in args), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)
    except OSError as err:
        raise ExperimentError('cannot ask run_experiment for the runs\' identities: rosrun: %s' % err.strerror)
    lines = proc.stdout.splitlines()
    if proc.returncode != 0 or len(lines) != len(args):
        raise ExperimentError('`run_experiment --identity` gave %d lines for %d runs (exit %d): %s'
                              % (len(lines), len(args), proc.returncode, proc.stderr.strip()[-1000:]))
    out = []
    for a, line in zip(args, lines):
        words = line.split('\t')
        if words[0] != 'ok' or len(words) != 3:
            raise ExperimentError('the run %s is refused: %s' % (' '.join(a), words[-1]))
        out.append((words[1], words[2]))
    return out


def _run(exp, controller, n, c, noise, pd, m, seed):
    args = [_word('controller', controller), _word('arena', exp['arena']), _word('n_robots', n),
            _word('seed', seed), _word('ticks', exp['ticks'])]
    args += [_word(k, c[k]) for k in CONDITION_KEYS if k in c]
    args += [_word(k, v) for k, v in m['words']]
    args += [_word(k, v) for k, v in noise['words'] + pd['words']]
    args += [_word(k, v) for k, v in sorted(exp['params'].items())]
    # The key (the record's name, with the run identity) is the core's: expand() asks for it.
    what = '_'.join(x for x in (c['label'], noise['label'], pd['label'], m['label']) if x)
    group = '%s_n%d_%s' % (file_safe(controller), n, what)
    return {'key': None, 'identity': None, 'group': group, 'args': args, 'robot_ticks': n * exp['ticks'], 'seed': seed, 'ticks': exp['ticks'],
            'controller': controller, 'n': n, 'condition': c['label'], 'noise': noise['label'],
            'population': pd['label'], 'model': m['label'], 'setting': m['name']}


def graph_words(args, launch_args):
    """A run's run_experiment words as `forage` words: controller constants (<kind>/..., e.g. crw/...)
    become one controller_constants:={...} map, noise/<device>/<key> one noise:={...} map, the rest must
    be arguments of the launch file (`launch_args`, population/... among them); anything else is an
    ExperimentError, since the node graph would run without it."""
    words, constants, noise = [], {}, {}
    for word in args:
        name, value = word.split(':=', 1)
        section = max((k for k in controller_names() if name.startswith(k + '/')), key=len, default=None)
        if section:  # a plugin's section has a '/' of its own: <package>/<Class>/<key>
            constants.setdefault(section, {})[name[len(section) + 1:]] = yaml.safe_load(value)
        elif name.startswith('noise/') and name.count('/') == 2:  # noise/<device>/<key>: the noise:= map
            _, device, key = name.split('/')
            noise.setdefault(device, {})[key] = yaml.safe_load(value)
        elif name in launch_args:
            words.append(word)
        else:
            raise ExperimentError('params.%s cannot reach the node graph (foraging.launch has no argument %s): '
                                  'run this experiment headless (without --graph)' % (name, name))
    if constants:
        words.append('controller_constants:=' + yaml.safe_dump(constants, default_flow_style=True).strip())
    if noise:
        words.append('noise:=' + yaml.safe_dump(noise, default_flow_style=True).strip())
    return words

