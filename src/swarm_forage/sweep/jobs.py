"""How a sweep's runs are started: the run table and run_one.sh (write_plan), GNU Parallel on this host or
--sshlogin hosts (run_local), SLURM job arrays resubmitted past time limits (run_slurm), and the wait that
shows progress and passes Ctrl-C or SIGTERM on (wait)."""
import os
import shlex
import signal
import subprocess

from swarm_forage.sweep import forks, slurm

PROG = 'sweep'
CHANGED = 'identity_changed.txt'  # the keys of runs that refused to start: their inputs changed since the plan
# Variables GNU Parallel passes to --sshlogin hosts (--env): the workspace (the same path there) and ROS's.
REMOTE_ENV = ('ROS_', 'CMAKE_PREFIX_PATH', 'PYTHONPATH', 'LD_LIBRARY_PATH', 'PKG_CONFIG_PATH', 'PATH')


class Terminated(Exception):
    """SIGTERM or SIGHUP: stops the runs in flight as Ctrl-C does."""


def program(name):
    """The words that start this package's program `name`: its path as rosrun finds it, looked up once, or
    rosrun itself if none is found. rosrun looks the program up on every call, which costs a run about 0.25 s
    of CPU (two catkin_find processes), several times what a short run of the paper's study costs."""
    try:
        proc = subprocess.run(['catkin_find', '--without-underlays', '--libexec', 'swarm_forage'],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    except OSError:  # no catkin_find
        proc = None
    for folder in proc.stdout.split() if proc else []:
        path = os.path.join(folder, name)
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return [path]
    return ['rosrun', 'swarm_forage', name]


def write_plan(out, runs, todo, exp, graph, threads, extra, compression='bz2'):
    """Writes the run table (KEY, then its words, tab-separated), the forks' extra words (forks.tsv), the
    one-run script and the to-do lists (the forks' apart: they start from their sources' checkpoints).
    run_one.sh deletes nothing: the sweep cleared its own leftovers under the lock, and a recorder
    writes to a temporary name of its own and never replaces a finished record."""
    folder = os.path.join(out, 'runs')
    table = os.path.join(out, 'runs.tsv')
    with open(table, 'w') as f:
        f.write(''.join('\t'.join([r['key']] + r['words']) + '\n' for r in runs))
    forks.write_table(out, extra)
    os.makedirs(os.path.join(out, 'checkpoints'), exist_ok=True)
    setup = next((os.path.join(p, 'setup.bash') for p in os.environ.get('CMAKE_PREFIX_PATH', '').split(':')
                  if os.path.isfile(os.path.join(p, 'setup.bash'))), '/dev/null')
    # Runs side by side share the cores: each gets its share of worker threads (results do not depend on it).
    # One snapshot a run (tables read the per-tick series); run_experiment's record_every ends at 10^6.
    record = ['bag:=$dir/$key.bag', 'label:=$key', 'compression:=' + compression,
              'record_every:=%d' % min(exp['ticks'], 1000000),
              'threads:=%d' % threads]
    record = ' '.join('"%s"' % w for w in record)
    if graph:  # a private master per job slot; no metrics_node (the tables come from the bags)
        command = ('ROS_MASTER_URI=http://localhost:$((11700 + slot)) exec rosrun swarm_forage forage '
                   'metrics:=false wait_for_subscribers:=0 record:=true %s "${args[@]}"' % record)
    else:  # exit code 3: the run's identity is not the planned one (an input changed): noted for the sweep
        command = ('%s "${args[@]}" %s &\npid=$!\ntrap \'kill -TERM $pid 2>/dev/null\' TERM HUP\n'
                   'trap \'kill -INT $pid 2>/dev/null\' INT\n'
                   'while :; do wait $pid; rc=$?; kill -0 $pid 2>/dev/null || break; done\n'
                   '[ $rc != 3 ] || echo "$key" >> %s\nexit $rc'
                   % (' '.join(shlex.quote(w) for w in program('run_experiment')), record,
                      shlex.quote(os.path.join(out, CHANGED))))
    script = os.path.join(out, 'run_one.sh')
    with open(script, 'w') as f:
        f.write('#!/bin/bash\n# One run of the sweep: run_one.sh KEY [SLOT] (written by sweep; deletes nothing).\n'
                'set -u\n'
                '[ -n "${ROS_PACKAGE_PATH:-}" ] || source %s\n'
                'key=$1; slot=${2:-1}; dir=%s\n'
                'line=$(awk -F"\\t" -v k="$key" \'$1 == k {print; exit}\' %s)\n'
                '[ -n "$line" ] || { echo "run_one.sh: no run $key" >&2; exit 2; }\n'
                'IFS=$\'\\t\' read -r -a words <<< "$line"\n'
                'args=("${words[@]:1}")\n'
                'line=$(awk -F"\\t" -v k="$key" \'$1 == k {print; exit}\' %s)\n'
                'IFS=$\'\\t\' read -r -a more <<< "$line"\n'
                'for w in "${more[@]:1}"; do [[ $w == resume:=* && ! -f ${w#resume:=} ]] || args+=("$w"); done'
                '  # a fork\'s resume:= (none when no checkpoint was saved: from tick 0), a source\'s save_at:= and '
                'save:=, checkpoint_every:=\n'
                '[ -f "$dir/$key.bag" ] && exit 0  # done earlier\n'
                % (shlex.quote(setup), shlex.quote(folder), shlex.quote(table), shlex.quote(os.path.join(out, forks.TABLE)))
                + slurm.RESUME % shlex.quote(os.path.join(out, 'checkpoints')) + command + '\n')
    os.chmod(script, 0o755)
    for name, part in (('todo.txt', [r for r in todo if 'from_tick' not in r]),
                       (forks.TODO, [r for r in todo if 'from_tick' in r])):
        with open(os.path.join(out, name), 'w') as f:
            f.write(''.join(r['key'] + '\n' for r in part))


def run_local(out, a, progress, listing):
    cmd = ['parallel', '--will-cite', '-j', str(a.jobs), '--joblog', os.path.join(out, 'joblog.txt'),
           shlex.quote(os.path.join(out, 'run_one.sh')) + ' {} {%}']
    for login in a.sshlogin:
        cmd[1:1] = ['--sshlogin', login, '--workdir', '.']
    if a.slf:
        cmd[1:1] = ['--slf', a.slf, '--workdir', '.']
    if a.sshlogin or a.slf:  # a remote run gets this sweep's workspace and ROS environment (ROS_MASTER_URI, ...)
        cmd[1:1] = [w for v in sorted(os.environ) if v.startswith(REMOTE_ENV) for w in ('--env', v)]
    with open(os.path.join(out, listing)) as todo:
        proc = subprocess.Popen(cmd, stdin=todo, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        return wait(proc, progress)


def run_slurm(out, a, progress, listing, clear):
    """Job arrays until every run of `listing` has its record, or a submission moves nothing on (no new
    record, no new checkpoint): a run stopped by the time limit continues from its checkpoint."""
    with open(os.path.join(out, listing)) as f:
        keys = f.read().split()
    submission = 1
    while True:
        before = slurm.state(out, keys)
        result = submit(out, a, progress, listing)
        if result is None:
            return None
        after = slurm.state(out, keys)
        slurm.remove_done(out, keys)
        left = [k for k in keys if k not in after[0]]
        if not left or not slurm.moved(before, after):
            return result
        submission += 1
        listing = 'todo_submission%d.txt' % submission
        with open(os.path.join(out, listing), 'w') as f:
            f.write(''.join(k + '\n' for k in left))
        clear()  # the incomplete records of the stopped runs
        print('%s: %d runs without a record after the job array (time limit?), %d with a checkpoint: submission %d'
              % (PROG, len(left), sum(1 for k in left if k in after[1]), submission), flush=True)


def submit(out, a, progress, listing):
    with open(os.path.join(out, listing)) as f:
        tasks = (len(f.read().split()) + a.chunk - 1) // a.chunk
    script = os.path.join(out, 'sweep.sbatch')
    logs = os.path.join(out, 'slurm')
    os.makedirs(logs, exist_ok=True)
    with open(script, 'w') as f:
        f.write('#!/bin/bash\n#SBATCH --job-name=swarm_forage_sweep\n#SBATCH --array=1-%d\n#SBATCH --cpus-per-task=1\n'
                '# Array task i runs lines (i-1)*%d+1 ... i*%d of todo.txt, one after another.\n'
                'echo "array task $SLURM_ARRAY_TASK_ID on node ${SLURMD_NODENAME:-?}"\n'
                'first=$(( (SLURM_ARRAY_TASK_ID - 1) * %d + 1 ))\n'
                'sed -n "${first},$(( first + %d - 1 ))p" %s | while read -r key; do %s "$key" 1 || exit 1; done\n'
                % (tasks, a.chunk, a.chunk, a.chunk, a.chunk, shlex.quote(os.path.join(out, listing)),
                   shlex.quote(os.path.join(out, 'run_one.sh'))))
    print('%s: submitting %s (%d array tasks of %d runs)' % (PROG, script, tasks, a.chunk), flush=True)
    # Paths go on the command line, not into #SBATCH lines, which do not take quoted spaces.
    cmd = ['sbatch', '--wait', '--parsable', '--output=' + os.path.join(logs, '%A_%a.out')]
    cmd += ['--partition=' + a.partition] if a.partition else []
    cmd += ['--time=' + a.time] if a.time else []
    proc = subprocess.Popen(cmd + [script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return wait(proc, progress)


def wait(proc, progress):
    try:
        while proc.poll() is None:
            progress.update()
            try:
                proc.wait(timeout=1)
            except subprocess.TimeoutExpired:
                pass
    except (KeyboardInterrupt, Terminated):
        proc.send_signal(signal.SIGINT)
        proc.wait()
        progress.update(final=True)
        return None
    progress.update(final=True)
    err = proc.stderr.read() if proc.stderr else ''
    return proc.returncode, err
