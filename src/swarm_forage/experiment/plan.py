"""The runs of an experiment: one per controller, size, condition, robustness setting, model and seed.

A run's key is its record's file stem as the core names it (`run_experiment --identity`: runBagName, whose
last part is the run identity). The identity is computed by the core from everything that changes a run's
outcome, files by content (the arena's values, a series' digest, the constants), never by path, so an
edited input gives other keys and no record of the old inputs is taken for one of the new."""
import subprocess

import yaml

from swarm_forage.experiment import ExperimentError
from swarm_forage.experiment.file import CONDITION_KEYS, run_word
from swarm_forage.experiment.kinds import controller_names, file_safe


def expand(exp, group_runs=None):
    """One dict per run: key (file stem), args (run_experiment words), robot_ticks, and its group (group: the
    key without seed and hash). Seeds 1 ... runs per group: `group_runs` {group: runs} (sweep.rounds, a
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
    args = [run_word('controller', controller), run_word('arena', exp['arena']), run_word('n_robots', n),
            run_word('seed', seed), run_word('ticks', exp['ticks'])]
    args += [run_word(k, c[k]) for k in CONDITION_KEYS if k in c]
    args += [run_word(k, v) for k, v in m['words']]
    args += [run_word(k, v) for k, v in noise['words'] + pd['words']]
    args += [run_word(k, v) for k, v in sorted(exp['params'].items())]
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
