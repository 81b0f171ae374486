"""Runs foraging.launch and says how it ended: exit 0 only when every run reached its last tick.

usage: rosrun swarm_forage forage [--launch FILE] [ARG:=VALUE ...] [--help]

roslaunch itself exits 0 even when a required node died, so a script or a sweep cannot tell a finished
run from a broken one. This wrapper passes the arguments to `roslaunch swarm_forage FILE` (default
foraging.launch) together with `outcome:=` a file world_node appends each run's end to, streams the
launch's output, and then prints one line per run. It exits 1 with the reason when a run stopped early
(a dead or silent node, Ctrl-C, a world/reset mid-run, a step timeout), when a node died with an error,
or when no run ended at all; 2 when no run ended because a node refused its parameters (an unknown
controller, a constant out of range: the node said which). An argument the launch file does not declare
is refused (exit 2) with the valid ones: roslaunch itself would ignore `n_robot:=5` silently. nodelet:=true runs the same graph as
nodelets in one process. --launch picks another launch file: one of the package (view.launch,
record.launch) or the path of your own (e.g. a rospy controller's graph), which must include
foraging.launch with pass_all_args="true"; the arguments of a file it includes with pass_all_args count
as its own. Killed (SIGTERM, SIGHUP) or interrupted (Ctrl-C), it shuts the launch down and leaves no
temporary file.

examples:
    rosrun swarm_forage forage controller:=dpo n_robots:=128 ticks:=6000
    rosrun swarm_forage forage record:=true bag:=$PWD/run.bag seed:=3 compression:=bz2
    rosrun swarm_forage forage nodelet:=true n_robots:=1024
    rosrun swarm_forage forage --launch record.launch bag:=$PWD/run.bag nodelet:=true
    rosrun swarm_forage forage --launch $PWD/my_graph.launch n_robots:=32"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import roslaunch.core
import roslaunch.rlutil
import roslaunch.substitution_args
import yaml

from swarm_forage.graph import launch_args

PROG = "forage"
DIED = re.compile(r"\[([\w./-]+)\] process has died \[pid \d+, exit code (-?\d+)")
REQUIRED = re.compile(r"REQUIRED process \[([\w./-]+)\] has died")
REFUSED = re.compile(r"process has died \[pid \d+, exit code 2\b")  # a node refused its parameters
# A launch file not found, not XML, or including one that cannot be resolved.
UNREADABLE = (roslaunch.core.RLException, roslaunch.substitution_args.SubstitutionException, ET.ParseError, OSError)
ERROR = re.compile(r"(run \d+ stopped at tick .*|still waiting after ~startup_timeout.*)")


class Terminated(Exception):
    """SIGTERM or SIGHUP: shut the launch down as Ctrl-C does."""


def terminated(signum, _frame):
    raise Terminated(signal.Signals(signum).name)


def is_path(launch):
    """A launch file given by its path (your own) rather than by its name in the package."""
    return os.sep in launch or os.path.isfile(launch)


def launch_words(launch):
    """What roslaunch is given to find `launch`."""
    return [os.path.abspath(launch)] if is_path(launch) else ["swarm_forage", launch]


def declared_args(launch):
    """The <arg>s `launch` declares that a caller may set (roslaunch ignores any other silently)."""
    if is_path(launch):
        if not os.path.isfile(launch):
            raise OSError("launch file %s does not exist" % launch)
        return launch_args.file_args(launch)
    # As roslaunch finds it; a file it includes with pass_all_args counts as its own.
    return launch_args.file_args(roslaunch.rlutil.resolve_launch_arguments(["swarm_forage", launch])[0])


def usage(launch):
    """This text and the launch file's own arguments, their defaults and docs."""
    print(__doc__)
    try:
        args = declared_args(launch)
    except UNREADABLE as err:
        print("(the arguments of %s cannot be listed: %s)" % (launch, err))
        return
    print("arguments of %s (NAME:=VALUE; default in brackets):" % launch)
    for e in args:
        print("  %-22s [%s] %s" % (e.get("name"), e.get("default", ""), e.get("doc", "")))


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    launch = "foraging.launch"
    if len(argv) >= 2 and argv[0] == "--launch":
        launch, argv = argv[1], argv[2:]
    if any(a in ("-h", "--help") for a in argv):
        usage(launch)
        return 0
    bad = [a for a in argv if ":=" not in a]
    if bad:
        print("%s: arguments are roslaunch arguments NAME:=VALUE (got %s)" % (PROG, " ".join(bad)), file=sys.stderr)
        return 2
    try:
        valid = [a.get("name") for a in declared_args(launch)]
    except UNREADABLE as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    unknown = [a.split(":=", 1)[0] for a in argv if a.split(":=", 1)[0] not in valid]
    if unknown:
        print("%s: %s declares no argument %s; valid: %s" % (PROG, launch, ", ".join(unknown), ", ".join(valid)),
              file=sys.stderr)
        return 2
    if "outcome" not in valid:  # world_node would tell nobody how the run ended
        print('%s: %s declares no argument outcome: include foraging.launch with pass_all_args="true"'
              % (PROG, launch), file=sys.stderr)
        return 2
    # The name first, then the file: a signal between creating it and knowing its name would leave it behind.
    outcome = os.path.join(tempfile.gettempdir(), "swarm_forage_outcome_%d_%d.yaml" % (os.getpid(), time.time_ns()))
    for sig in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, terminated)
    try:
        os.close(os.open(outcome, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
        return launched(launch, argv, outcome)
    except (KeyboardInterrupt, Terminated) as e:  # before the launch started, or a second signal
        print("%s: %s" % (PROG, "interrupted (Ctrl-C)" if isinstance(e, KeyboardInterrupt) else "terminated (%s)" % e),
              file=sys.stderr)
        return 1
    finally:
        if os.path.exists(outcome):
            os.unlink(outcome)


def launched(launch, argv, outcome):
    """Runs the launch with `outcome`, streams its output and returns forage's exit code."""
    cmd = ["roslaunch"] + launch_words(launch) + ["outcome:=" + outcome] + argv
    died, errors, refused = [], [], False
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
    try:
        for line in proc.stdout:
            sys.stdout.write(line)
            sys.stdout.flush()  # line by line into a pipe too (a sweep's log, a test)
            plain = re.sub(r"\x1b\[[0-9;]*m", "", line)
            m = DIED.search(plain)
            if m and m.group(2) != "0":
                died.append("%s exited with code %s" % (m.group(1), m.group(2)))
            refused = refused or REFUSED.search(plain) is not None
            m = REQUIRED.search(plain)
            if m:
                died.append("required node %s ended, which ends the launch" % m.group(1))
            m = ERROR.search(plain)
            if m:
                errors.append(m.group(1))
        proc.wait()
    except (KeyboardInterrupt, Terminated) as e:  # shut the nodes down through roslaunch, as Ctrl-C does
        died.append("interrupted (Ctrl-C)" if isinstance(e, KeyboardInterrupt) else "terminated (%s)" % e)
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        proc.send_signal(signal.SIGINT)  # roslaunch got a Ctrl-C from the terminal too: a second one is harmless
        for line in proc.stdout:
            sys.stdout.write(line)
        proc.wait()
    with open(outcome) as f:
        runs = yaml.safe_load(f) or []

    status = 0
    for r in runs:
        where = "; bag: %s" % r["bag"] if r.get("bag") else ""
        if r["complete"]:
            print("%s: run %d complete: %d of %d ticks%s" % (PROG, r["run"], r["ticks_done"], r["ticks"], where))
        else:
            print("%s: run %d stopped at tick %d of %d (%s)%s" % (PROG, r["run"], r["ticks_done"], r["ticks"],
                                                                 r["reason"], where), file=sys.stderr)
            status = 1
    if not runs:
        why = "; ".join(errors + died) or "world_node ended no run (see the log above)"
        print("%s: no run ended: %s" % (PROG, why), file=sys.stderr)
        status = 1
    crashed = [d for d in died if "exited with code" in d or "interrupted" in d or "terminated" in d]
    if crashed or (status and died):  # also name the node whose end ended the launch
        print("%s: %s" % (PROG, "; ".join(died)), file=sys.stderr)
        status = 1
    if proc.returncode != 0:
        print("%s: roslaunch exited with code %d" % (PROG, proc.returncode), file=sys.stderr)
        status = 1
    if not runs and refused:
        status = 2  # a node refused its parameters at start-up (e.g. an unknown controller): said above
    return status

