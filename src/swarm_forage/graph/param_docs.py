"""The parameter table's other forms: docs/nodes-and-parameters.md's tables are made from it (`param_table
--yaml`, the one declaration: src/ros/params/param_table.cpp) and from foraging.launch's arguments, and the
launch files' argument docs are checked against it: a parameter a launch file sets must exist, and an argument's
doc may not give another range, leave out a valid value or hide a default that differs from the node's.

rosrun swarm_forage param_docs [--check | --write] [--doc FILE] [--launch DIR]
  (no option: print the tables; --check: exit 1 naming every table or argument that drifted; --write: remake
  the tables between the doc's markers, then check the launch files)
"""
import argparse
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import rospkg
import yaml

from swarm_forage.graph import launch_args

PACKAGE = rospkg.RosPack().get_path('swarm_forage')
DOC = os.path.join(PACKAGE, 'docs', 'nodes-and-parameters.md')
LAUNCH = os.path.join(PACKAGE, 'launch')
GRAPH = 'foraging.launch'
BEGIN = '<!-- param_docs: %s -->'
END = '<!-- param_docs: end -->'
# The launch file's nodes and the table's readers.
NODES = {'world': 'world_node', 'controller': 'controller_node', 'environment': 'environment_node',
         'metrics': 'metrics_node'}
# A launch argument whose default is not the node's says so, and the node's default is checked too.
NODE_DEFAULT = re.compile(r'\(node default: ([^)]*)\)')
RANGE = re.compile(r'\[(-?[0-9.e+]+), (-?[0-9.e+]+)\]')


class DocsError(Exception):
    pass


def load_table():
    """`param_table --yaml`: the readers and every parameter's row."""
    try:
        proc = subprocess.run(['rosrun', 'swarm_forage', 'param_table', '--yaml'], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)
    except OSError as err:
        raise DocsError('cannot run param_table: %s (source the workspace setup.bash)' % err.strerror)
    table = yaml.safe_load(proc.stdout) if proc.returncode == 0 else None
    if not isinstance(table, dict) or not table.get('parameters'):
        raise DocsError('`param_table --yaml` did not list the parameters (exit %d): %s'
                        % (proc.returncode, (proc.stdout + proc.stderr).strip()))
    return table


def cell(text):
    """`text` in a table's cell: a | would end the cell, <x> would read as HTML, * as emphasis."""
    return re.sub(r'([|<>*])', r'\\\1', str(text))


def code(text):
    """`text` as code in a table's cell (only a | needs escaping there)."""
    return '`%s`' % str(text).replace('|', '\\|')


def shown_default(row):
    d = row['default']
    if d == '':
        return '(empty)'
    return code(d) if row['type'] in ('text', 'choice', 'condition', 'section') and not _number(d) else d


def _number(text):
    try:
        float(text)
        return True
    except (TypeError, ValueError):
        return False


def reader_rows(table, reader):
    """The rows a doc table lists for `reader`: run_experiment's own only (the nodes' tables give the rest)."""
    rows = [r for r in table['parameters'] if reader in r['readers']]
    if reader == 'run_experiment':
        rows = [r for r in rows if not set(r['readers']) & set(NODES.values())]
    return rows


def parameter_table(table, reader):
    lines = ['| parameter | default | valid | meaning |', '|---|---|---|---|']
    for r in reader_rows(table, reader):
        lines.append('| %s | %s | %s | %s |' % (code(r['name']), shown_default(r), cell(r['valid']), cell(r['doc'])))
    return lines


def argument_table(path):
    """foraging.launch's arguments as the docs list them: name, default, doc (the launch file's own words)."""
    lines = ['| argument | default | meaning |', '|---|---|---|']
    for a in ET.parse(path).getroot().findall('arg'):
        if a.get('value') is not None:
            continue
        default = a.get('default')
        shown = '(required)' if default is None else '(empty)' if default == '' else code(default)
        lines.append('| %s | %s | %s |' % (code(a.get('name')), shown, cell(a.get('doc', ''))))
    return lines


def tables(table, launch_dir):
    """{marker name: lines} of every table the doc holds."""
    out = {r: parameter_table(table, r) for r in list(NODES.values()) + ['run_experiment']}
    out[GRAPH] = argument_table(os.path.join(launch_dir, GRAPH))
    return out


def splice(text, blocks, where):
    """`text` with each block between its markers; DocsError for a missing marker."""
    for name, lines in blocks.items():
        begin = BEGIN % name
        if begin not in text or END not in text.split(begin, 1)[1]:
            raise DocsError('%s has no %s ... %s markers' % (where, begin, END))
        head, rest = text.split(begin, 1)
        tail = rest.split(END, 1)[1]
        text = head + begin + '\n' + '\n'.join(lines) + '\n' + END + tail
    return text


def drifted(text, blocks):
    """The names of the blocks whose copy in `text` is not what the table makes."""
    return [name for name, lines in blocks.items() if splice(text, {name: lines}, '') != text]


def _choices(valid):
    """The values a row's valid text lists after "one of", or []."""
    if not valid.startswith('one of '):
        return []
    listed = valid[len('one of '):].split(' (')[0].split(' or ')[0]
    return [c.strip() for c in listed.split(',') if c.strip()]


def _same(a, b):
    if _number(a) and _number(b):
        return float(a) == float(b)
    return str(a).strip().lower() == str(b).strip().lower()


def graph_parameters(path):
    """{argument: [(reader, parameter)]}: the node parameters each argument of the graph sets as it is."""
    out = {}
    for node in ET.parse(path).getroot().findall('node'):
        reader = NODES.get(node.get('name'))
        if reader is None:
            continue
        for p in node.findall('param'):
            m = re.fullmatch(r'\$\(arg ([\w/]+)\)', p.get('value', ''))
            if m:
                out.setdefault(m.group(1), []).append((reader, p.get('name')))
        for p in node.findall('rosparam'):
            m = re.fullmatch(r'\$\(arg ([\w/]+)\)', (p.text or '').strip())
            if m and p.get('param'):
                out.setdefault(m.group(1), []).append((reader, p.get('param') + '/'))
    return out


def _row(table, reader, name):
    for r in table['parameters']:
        if reader in r['readers'] and (r['name'] == name or (r['type'] == 'section' and r['name'] == name[:len(
                r['name'])] and r['name'].endswith('/'))):
            return r
    return None


def file_parameters(path, launch_dir):
    """graph_parameters of `path` and of the files it includes with pass_all_args (looked up in `launch_dir`),
    but for the arguments the include sets itself."""
    out = graph_parameters(path)
    for inc in ET.parse(path).getroot().findall('include'):
        if inc.get('pass_all_args') != 'true':
            continue
        fixed = {a.get('name') for a in inc.findall('arg')}
        inner = file_parameters(os.path.join(launch_dir, os.path.basename(inc.get('file'))), launch_dir)
        for arg, targets in inner.items():
            if arg not in fixed:
                out.setdefault(arg, []).extend(targets)
    return out


def launch_problems(table, launch_dir):
    """What in the launch files disagrees with the table, one line each."""
    problems = []
    for fname in sorted(f for f in os.listdir(launch_dir) if f.endswith('.launch')):
        path = os.path.join(launch_dir, fname)
        for arg, targets in sorted(graph_parameters(path).items()):
            for reader, name in targets:
                if _row(table, reader, name) is None:
                    problems.append('%s: argument %s sets ~%s, which is not a parameter of %s'
                                    % (fname, arg, name, reader))
        sets = file_parameters(path, launch_dir)
        for a in launch_args.file_args(path, own_only=True):
            name, doc, default = a.get('name'), a.get('doc'), a.get('default')
            rows = [r for r in (_row(table, rd, p) for rd, p in sets.get(name, [])) if r]
            where = '%s: argument %s' % (fname, name)
            for r in rows:
                problems += _arg_problems(where, doc or '', default, r)
    return problems


def _arg_problems(where, doc, default, r):
    """How the doc and default of an argument that sets the parameter of row `r` disagree with it."""
    problems = []
    if r['type'] == 'section':  # a map of keys, each checked by its node
        return problems
    got, want = RANGE.search(doc), RANGE.search(r['valid'])
    if got and (not want or not (_same(got.group(1), want.group(1)) and _same(got.group(2), want.group(2)))):
        problems.append('%s: its doc says %s where ~%s is %s' % (where, got.group(0), r['name'], r['valid']))
    missing = [c for c in _choices(r['valid']) if not re.search(r'(?<![\w/])%s(?![\w/])' % re.escape(c), doc)]
    if doc and missing:
        problems.append('%s: its doc leaves out %s of ~%s (%s)' % (where, ', '.join(missing), r['name'], r['valid']))
    said = NODE_DEFAULT.search(doc)
    if said and not _same(said.group(1), r['default']):
        problems.append('%s: its doc says (node default: %s) where ~%s defaults to %s'
                        % (where, said.group(1), r['name'], r['default'] or "''"))
    elif not said and default is not None and '$(' not in default and not _same(default, r['default']):
        problems.append('%s: default %s where ~%s defaults to %s: say "(node default: %s)" in its doc'
                        % (where, default or "''", r['name'], r['default'] or "''", r['default']))
    return problems


def main(argv=None):
    ap = argparse.ArgumentParser(prog='param_docs', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--check', action='store_true', help='exit 1 when the doc or a launch file drifted')
    ap.add_argument('--write', action='store_true', help="remake the doc's tables between their markers")
    ap.add_argument('--doc', default=DOC, help='the doc holding the tables (default: %(default)s)')
    ap.add_argument('--launch', default=LAUNCH, help='the launch files (default: %(default)s)')
    a = ap.parse_args(argv)
    try:
        table = load_table()
        blocks = tables(table, a.launch)
        if not (a.check or a.write):
            for name, lines in blocks.items():
                print('%s\n%s\n' % (BEGIN % name, '\n'.join(lines)))
            return 0
        with open(a.doc) as f:
            text = f.read()
        new = splice(text, blocks, a.doc)
        problems = launch_problems(table, a.launch)
    except (DocsError, OSError, ET.ParseError) as err:
        sys.stderr.write('param_docs: %s\n' % err)
        return 1
    if a.write and new != text:
        with open(a.doc, 'w') as f:
            f.write(new)
        print('param_docs: wrote %s' % a.doc)
    elif a.check:
        problems = ['%s: the table %s is not what the parameter table makes' % (a.doc, name)
                    for name in drifted(text, blocks)] + problems
    for p in problems:
        sys.stderr.write('param_docs: %s\n' % p)
    if problems:
        sys.stderr.write('param_docs: remake the docs with `rosrun swarm_forage param_docs --write`; fix the launch '
                         'files by hand\n')
        return 1
    print('param_docs: %s and %s are current' % (a.doc, a.launch))
    return 0
