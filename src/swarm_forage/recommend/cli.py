"""`recommend`: the (controller, N) a target calls for, ranked from a run library (docs/recommend.md).

Candidates are every controller of the target's arena at each measured N <= robots, and at the sizes its
fitted P(N) (recommend.model) gives between them and up to two doublings beyond (powers of two and N*,
<= robots; marked "fitted"). Each criterion is normalised across the candidates by min-max, 1 for the best and 0 for the worst
(P, Z and robustness higher-better; e, R and A lower-better; an undefined value scores 0), and the score is
the weighted mean sum(w_k s_k) / sum(w_k), in [0, 1]."""
import argparse
import os
import sys

from swarm_forage.paths import PACKAGE
from swarm_forage.recommend import library as lib
from swarm_forage.recommend import target
from swarm_forage.recommend.rank import candidates, score
from swarm_forage.recommend.report import missing, render, shown
from swarm_forage.study import claims

PROG = 'recommend'


def options():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('target', help='target YAML (config/targets/*.yaml; keys: docs/recommend.md)')
    p.add_argument('sweeps', nargs='*', help='sweep folders (sweep --out), or study folders holding them (paper\'s '
                   'results/paper_96, its copy docs/paper_96); default: the folders under PACKAGE/results (one or '
                   'two levels down) that hold tables/')
    p.add_argument('--output', help='also write the text there')
    p.add_argument('--figure', help='the figure (PNG; default: next to --output, else ./recommend.png)')
    return p


def load_target(path):
    """The target, checked: R and A need a condition that changes."""
    t = target.load(path)
    for k in ('reactivity', 'adaptability'):
        if t['weights'][k] > 0 and all(w == 'null' for w, _ in t['conditions']):
            raise target.TargetError('weights.%s needs conditions other than ideal (R and A measure a change)' % k)
    return t


def library_candidates(folders, t, package):
    """(library, candidates, fits) of the sweep folders (default: those under PACKAGE/results); a library
    that cannot answer the target is a LibraryError saying what would measure it."""
    folders = folders or lib.default_sweeps(package)
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
                                   '\n  rosrun swarm_forage sweep $(rospack find swarm_forage)/config/experiments/'
                                   'robustness_%s_32x16.yaml --runs 3' % m
                                   for k, m in (('noise', 'saa'), ('population', 'pd')) if t[k] is not None))
    cands, fits = candidates(library, t)
    if not cands:
        raise lib.LibraryError('no candidate with N <= %d robots in %s (smallest measured: %s); measure one with:'
                               % (t['robots'], t['arena'], min(n for c in library.controllers(t['arena'])
                                                               for n in library.sizes(t['arena'], c))) +
                               ''.join('\n- %s:\n  %s' % (what, cmd.replace('\n', '\n  '))
                                       for what, cmd in missing(library, t, cands, package)))
    return library, cands, fits


def main(argv=None, package=PACKAGE):
    """The recommend command (this module's docstring); returns its exit status: 0 done, 1 the library lacks
    data or holds incomplete sweeps, 2 bad input. `package`: the folder whose results/ is the default library."""
    a = options().parse_args(argv)
    try:
        t = load_target(a.target)
    except target.TargetError as err:
        print('%s: %s: %s' % (PROG, a.target, err), file=sys.stderr)
        return 2
    try:
        library, cands, fits = library_candidates(a.sweeps, t, package)
    except (lib.LibraryError, lib.runs.TableMissing) as err:
        print('%s: %s' % (PROG, err), file=sys.stderr)
        return 1
    weights = {k: w for k, w in t['weights'].items() if w > 0}
    ranked = score(cands, weights)
    text = render(t, library, ranked, fits, weights, missing(library, t, cands, package))
    path = a.figure or os.path.join(os.path.dirname(os.path.abspath(a.output)) if a.output else os.getcwd(),
                                    'recommend.png')
    from swarm_forage.recommend import figure  # here: matplotlib only once there is a figure to draw
    figure.draw(path, ranked, fits, library, t, weights)
    text += '\nFigure: %s\n' % shown(path)
    if a.output:
        tmp = a.output + '.%d.tmp' % os.getpid()
        with open(tmp, 'w') as f:
            f.write(text)
        os.replace(tmp, a.output)
    print(text, end='')
    return 0
