"""The reports' `recommend` section and --publish: what `recommend` makes of the paper's target on a study
(called in this process, from the package's folder as a reader would run it), and a study's copy as it is
committed (docs/paper_96, docs/paper_quick)."""
import contextlib
import io
import json
import os
import shutil
import sys

from swarm_forage.paths import PACKAGE
from swarm_forage.recommend import cli as recommend_cli
from swarm_forage.study.steps import call

TARGET = os.path.join(PACKAGE, 'config', 'targets', 'paper_section5.yaml')
SECTION = '## `recommend` on the paper\'s target'


def shown(path, cwd):
    """A path as a reader types it from `cwd`: relative when inside it, else absolute."""
    rel = os.path.relpath(path, cwd)
    return os.path.abspath(path) if rel == os.pardir or rel.startswith(os.pardir + os.sep) else rel


def report_model(study):
    """The model a study's report.md names on its **Model:** line (paper_report.py), or None."""
    try:
        with open(os.path.join(study, 'report.md')) as f:
            line = next((x for x in f if x.startswith('**Model')), '')
    except OSError:
        return None
    return line.split(':**', 1)[1].split()[0].rstrip(';,') if ':**' in line else None


def recommend(argv):
    """`recommend ARGV` from the package's folder: (its exit status, what it printed, stdout and stderr as one)."""
    printed = io.StringIO()
    cwd = os.getcwd()
    os.chdir(PACKAGE)
    try:
        with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
            code = call(recommend_cli.main, argv)
    finally:
        os.chdir(cwd)
    return code, printed.getvalue()


def recommend_section(out):
    """What `recommend` makes of the paper's target (config/targets/paper_section5.yaml) on the arm in OUT (a
    study folder: `recommend` reads the sweep folders inside it) and the reduced study's time-varying sweep
    beside it (OUT's sibling paper_quick...: results/paper_quick, or docs/paper_quick for a --publish copy), run
    from the package's folder as a reader would: OUT/recommend.txt and recommend.png, and as the last section
    of OUT/report.md (replacing the one there), with whether that is §5's "CRW with ~8,192". The sibling's
    sweep is left out when its report names another model than OUT's."""
    quick = os.path.join(os.path.dirname(out), os.path.basename(out).replace('paper_96', 'paper_quick'))
    tv = os.path.join(quick, 'time_varying_64x32')
    same_model = report_model(quick) == report_model(out)  # never one model's arm beside the other's sweep
    library = [out] + ([tv] if same_model and os.path.isfile(os.path.join(tv, 'tables', 'series.csv')) else [])
    text_path, figure = os.path.join(out, 'recommend.txt'), os.path.join(out, 'recommend.png')
    command = [shown(TARGET, PACKAGE)] + [shown(f, PACKAGE) for f in library]
    code, printed = recommend(command + ['--output', shown(text_path, PACKAGE), '--figure', shown(figure, PACKAGE)])
    top = next((line for line in printed.splitlines() if line.startswith('Recommended:')), None)
    words = top.split() if top else []
    agrees = len(words) > 5 and words[1] == 'crw' and words[5].isdigit() and 4096 <= int(words[5]) <= 8192
    verdict = ('agrees with §5\'s "CRW with ~8,192"' if agrees else 'does not agree with §5\'s "CRW with ~8,192"'
               if top else 'makes no recommendation (exit %d)' % code)
    lines = [SECTION, '', '`rosrun swarm_forage recommend %s` %s.' % (' '.join(command), verdict), '', '```'] + \
        printed.rstrip().splitlines() + ['```', '']
    if os.path.exists(figure):
        lines += ['![recommend](%s)' % os.path.relpath(figure, out), '']
    path = os.path.join(out, 'report.md')
    with open(path) as f:
        report = f.read()
    if SECTION in report:  # a report copied with its section: the section anew, whatever follows it kept
        head, tail = report.split(SECTION, 1)
        rest = tail.split('\n## ', 1)
        report = head.rstrip('\n') + '\n\n' + '\n'.join(lines) + ('\n## ' + rest[1] if len(rest) > 1 else '')
    else:
        report = report + '\n'.join(lines) + '\n'
    with open(path, 'w') as f:
        f.write(report if report.endswith('\n') else report + '\n')
    print('paper: recommend %s' % verdict)


def publish(out, plan, dest, arm_96):
    """--publish DEST: the study as it is committed (docs/paper_96, docs/paper_quick): report.md, verdicts.json
    and figures/ of OUT, and every sweep's tables/ (all of them, as run_tables wrote them) in DEST/<sweep>/tables/,
    the layout `recommend TARGET DEST` reads (no record: a run is not redone from a copy). The folders
    verdicts.json names become DEST's, relative to the package. Then the arm's `recommend` section is made anew
    on DEST (and on the reduced study's copy beside it, DEST's sibling paper_quick...); publishing the reduced
    study remakes the section of the arm's copy beside it, where there is one."""
    dest = os.path.abspath(dest)
    if os.path.realpath(dest) == os.path.realpath(out):
        sys.exit('paper: --publish %s: that is the study\'s own folder; give another (docs/paper_96)' % dest)
    os.makedirs(dest, exist_ok=True)
    for n, _, _ in plan:
        tables = os.path.join(out, n, 'tables')
        if os.path.isdir(tables):
            shutil.rmtree(os.path.join(dest, n, 'tables'), ignore_errors=True)
            shutil.copytree(tables, os.path.join(dest, n, 'tables'))
    if os.path.isdir(os.path.join(out, 'figures')):
        shutil.rmtree(os.path.join(dest, 'figures'), ignore_errors=True)
        shutil.copytree(os.path.join(out, 'figures'), os.path.join(dest, 'figures'))
    shutil.copyfile(os.path.join(out, 'report.md'), os.path.join(dest, 'report.md'))
    verdicts = os.path.join(out, 'verdicts.json')
    if os.path.isfile(verdicts):
        with open(verdicts) as f:
            claims = json.load(f)
        for c in claims:
            for g in c.get('groups', []):
                if g and os.path.dirname(os.path.abspath(g[0])) == out:
                    g[0] = shown(os.path.join(dest, os.path.basename(g[0])), PACKAGE)
        with open(os.path.join(dest, 'verdicts.json'), 'w') as f:
            json.dump(claims, f, indent=1, ensure_ascii=False)
            f.write('\n')
    arm = dest if arm_96 else os.path.join(os.path.dirname(dest),
                                           os.path.basename(dest).replace('paper_quick', 'paper_96'))
    if not arm_96 and (arm == dest or not os.path.isfile(os.path.join(arm, 'report.md'))):
        arm = None  # no arm's copy beside this one (the full study's report has no recommend section)
    if arm:
        recommend_section(arm)
    print('paper: published in %s%s' % (dest, ' (and remade the recommend section of %s)' % arm
                                         if arm and arm != dest else ''))
