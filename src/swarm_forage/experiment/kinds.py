"""The controller kinds of this build (`run_experiment --controllers`): what experiment files, tables and
figures name controllers by."""
import functools
import subprocess

import yaml

from swarm_forage.experiment import ExperimentError


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
