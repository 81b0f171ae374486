"""The models and quirks of this build (`run_experiment --models`): one model choice checked, its words and
label, and the model as an axis of settings (an experiment's `models`, `sweep --models`)."""
import functools
import subprocess

import yaml

from swarm_forage.experiment import ExperimentError

# An experiment file's `models` key.
AXIS = ('the model as an axis: a list of settings, each MODEL, MODEL+QUIRK[+QUIRK ...] or MODEL+each (one '
        'setting per quirk the model lacks, alone), or a map {model: MODEL, quirks: [QUIRK, ...] or each}; '
        'e.g. [swarm_forage, fordyca_2019, swarm_forage+each]')


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


def setting(model, quirks):
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
        raise ExperimentError('%s must be %s' % (where, AXIS))
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
            out.append(setting(model, chosen))
    if not out:
        raise ExperimentError('%s gives no setting (each quirk is already in its model)' % where)
    return out
