#!/usr/bin/env python3
"""sweep --sshlogin across two hosts, for real. The second host is a network
namespace of its own (`ip netns`) joined by a veth pair on 10.231.S.0/30 (S of this test's pid), with
Debian's openssh-server started inside it on a port of its own, a host key and a user key this test
generates; it shares the file system, so the workspace is at the same path. A tiny sweep split between
this host (`:`) and that one must give the records and tables of a local sweep, and both hosts must
have run runs (GNU Parallel's joblog names the host of each). The same namespace holds the second node
of a two-node SLURM (test/sweep/slurm_cluster.sh with SLURM_SECOND_NODE: a slurmd of its own there): a
--slurm sweep's array tasks run on both nodes and give the local tables. The namespace, the veth pair,
sshd, the SLURM daemons and the temporary files are removed even when the test fails. Needs root, ip,
sshd, slurm (make deps)."""
import csv
import glob
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from root_only import needs_root, rosrun  # noqa: E402
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import SWEEP, TINY, sweep  # noqa: E402

TAG = 'sfs%d' % (os.getpid() % 100000)  # names of this test's namespace and links (<= 15 characters)
SUBNET = '10.231.%d' % (os.getpid() % 250)
PORT = 22000 + os.getpid() % 1000
CLUSTER = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'slurm_cluster.sh')


def sh(*cmd, check=True):
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    if check and proc.returncode != 0:
        raise RuntimeError('%s failed (%d): %s' % (' '.join(cmd), proc.returncode, proc.stdout))
    return proc.stdout


class SecondHost:
    """A network namespace with its own sshd: the second host. `close` undoes every step taken so far."""

    def __init__(self, tmp):
        self.tmp, self.ns, self.veth, self.sshd_pid, self.made_privsep = tmp, TAG, TAG + 'a', None, False
        self.address = SUBNET + '.2'

    def open(self):
        self.network()
        self.sshd()

    def network(self):
        self.close()  # a namespace of this name left by a killed test
        sh('ip', 'netns', 'add', self.ns)
        sh('ip', 'link', 'add', self.veth, 'type', 'veth', 'peer', 'name', TAG + 'b')
        sh('ip', 'link', 'set', TAG + 'b', 'netns', self.ns)
        sh('ip', 'addr', 'add', SUBNET + '.1/30', 'dev', self.veth)
        sh('ip', 'link', 'set', self.veth, 'up')
        inside = ['ip', 'netns', 'exec', self.ns]
        sh(*inside, 'ip', 'addr', 'add', self.address + '/30', 'dev', TAG + 'b')
        sh(*inside, 'ip', 'link', 'set', TAG + 'b', 'up')
        sh(*inside, 'ip', 'link', 'set', 'lo', 'up')

    def sshd(self):
        inside = ['ip', 'netns', 'exec', self.ns]
        for name in ('host_key', 'user_key'):
            sh('ssh-keygen', '-q', '-t', 'ed25519', '-N', '', '-C', TAG, '-f', os.path.join(self.tmp, name))
        with open(os.path.join(self.tmp, 'user_key.pub')) as f:
            write(self.tmp, 'authorized_keys', f.read())
        with open(os.path.join(self.tmp, 'host_key.pub')) as f:
            write(self.tmp, 'known_hosts', '[%s]:%d %s' % (self.address, PORT, f.read()))
        config = write(self.tmp, 'sshd_config', '\n'.join([
            'Port %d' % PORT, 'ListenAddress %s' % self.address, 'HostKey %s/host_key' % self.tmp,
            'AuthorizedKeysFile %s/authorized_keys' % self.tmp, 'PidFile %s/sshd.pid' % self.tmp,
            'PermitRootLogin prohibit-password', 'PasswordAuthentication no', 'KbdInteractiveAuthentication no',
            'UsePAM no', 'StrictModes no', 'LogLevel VERBOSE', 'MaxStartups 50', 'MaxSessions 50', '']))
        write(self.tmp, 'ssh_config', '\n'.join([
            'Host second', '  HostName %s' % self.address, '  Port %d' % PORT, '  User root',
            '  IdentityFile %s/user_key' % self.tmp, '  IdentitiesOnly yes', '  BatchMode yes',
            '  UserKnownHostsFile %s/known_hosts' % self.tmp, '  StrictHostKeyChecking yes', '']))
        if not os.path.isdir('/run/sshd'):  # sshd's privilege separation folder (the service makes it)
            os.makedirs('/run/sshd', 0o755)
            self.made_privsep = True
        sh(*inside, '/usr/sbin/sshd', '-f', config, '-E', os.path.join(self.tmp, 'sshd.log'))
        deadline = time.time() + 120
        while time.time() < deadline:
            if os.path.exists(os.path.join(self.tmp, 'sshd.pid')):
                with open(os.path.join(self.tmp, 'sshd.pid')) as f:
                    pid = f.read().strip()
                if not pid:  # sshd has made the file and not yet written it (seen on a loaded machine)
                    time.sleep(0.2)
                    continue
                self.sshd_pid = int(pid)
                if subprocess.run(self.ssh() + ['true'], timeout=30).returncode == 0:
                    return
            time.sleep(0.2)
        raise RuntimeError('sshd in namespace %s did not answer: %s' % (self.ns, self.log()))

    def ssh(self):
        return ['ssh', '-F', os.path.join(self.tmp, 'ssh_config'), 'second']

    def log(self):
        try:
            with open(os.path.join(self.tmp, 'sshd.log')) as f:
                return f.read()
        except OSError:
            return ''

    def close(self):
        if self.sshd_pid:
            try:
                os.kill(self.sshd_pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
            self.sshd_pid = None
        if self.ns in sh('ip', 'netns', 'list', check=False).split():
            # The sessions' processes live in the namespace: end them (by pid) before removing it.
            for pid in sh('ip', 'netns', 'pids', self.ns, check=False).split():
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except (ProcessLookupError, ValueError):
                    pass
            sh('ip', 'netns', 'del', self.ns, check=False)  # removes the peer, and with it the pair
        sh('ip', 'link', 'del', self.veth, check=False)
        if self.made_privsep:
            try:
                os.rmdir('/run/sshd')
            except OSError:
                pass
            self.made_privsep = False


def series_rows(out):
    with open(os.path.join(out, 'tables', 'series.csv')) as f:
        return f.read()


def local_sweep(tmp):
    """The tiny sweep run locally, once for both tests: the tables the others must equal."""
    out = os.path.join(tmp, 'local')
    if not os.path.isfile(os.path.join(out, 'tables', 'series.csv')):
        proc = subprocess.run(SWEEP + [write(tmp, 'tiny.yaml', TINY), '--out', out, '-j', '2'], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=600)
        assert proc.returncode == 0, proc.stdout
    return out


def same_tables(test, out, local):
    names = lambda d: sorted(os.path.basename(p) for p in glob.glob(os.path.join(d, 'runs', '*.bag')))
    test.assertEqual(names(out), names(local))
    test.assertEqual(len(names(out)), 8)
    for table in ('series.csv', 'scalability.csv', 'self_organization.csv', 'bootstrap.csv'):
        with open(os.path.join(out, 'tables', table)) as a, open(os.path.join(local, 'tables', table)) as b:
            test.assertEqual(a.read(), b.read(), table)


@needs_root('a second host in a network namespace with an sshd (and a slurmd) of its own')
class TwoHosts(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.shared = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_hosts_local_'))

    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_hosts_'))
        os.chmod(self.tmp, 0o700)
        self.host, self.cluster = SecondHost(self.tmp), None
        # SIGTERM (rostest's time limit) unwinds through tearDown like a failure.
        self.old = signal.signal(signal.SIGTERM, lambda *_: (_ for _ in ()).throw(SystemExit(143)))

    def tearDown(self):
        if self.cluster:
            subprocess.run([CLUSTER, 'stop', self.cluster], env=self.env, timeout=60)
        self.host.close()
        signal.signal(signal.SIGTERM, self.old)
        self.assertNotIn(TAG, sh('ip', 'netns', 'list', check=False).split(), 'the namespace is gone')
        self.assertNotIn(TAG + 'a', sh('ip', '-o', 'link', check=False), 'the veth pair is gone')

    def sweep(self, *args):
        return sweep(*args)

    def test_sweep_split_between_two_hosts_equals_a_local_sweep(self):
        local, split = local_sweep(self.shared), os.path.join(self.tmp, 'split')
        spec = write(self.tmp, 'tiny.yaml', TINY)
        self.host.open()
        login = '1/' + ' '.join(self.host.ssh())
        proc = self.sweep(spec, '--out', split, '-j', '1', '--sshlogin', ':', '--sshlogin', login)
        self.assertEqual(proc.returncode, 0, proc.stdout + self.host.log())
        same_tables(self, split, local)
        with open(os.path.join(split, 'joblog.txt')) as f:
            jobs = list(csv.DictReader(f, delimiter='\t'))
        hosts = {}
        for job in jobs:
            self.assertEqual(job['Exitval'], '0', job)
            hosts[job['Host'].strip()] = hosts.get(job['Host'].strip(), 0) + 1
        self.assertEqual(sum(hosts.values()), 8, hosts)
        self.assertEqual(len(hosts), 2, 'both hosts ran runs: %s' % hosts)
        self.assertIn('Accepted publickey for root', self.host.log(), 'the runs went through the namespace\'s sshd')

    def test_slurm_sweep_on_two_nodes_equals_a_local_sweep(self):
        """Two slurmd, one here and one in the namespace: a --slurm sweep's tasks run on both."""
        local = local_sweep(self.shared)
        self.host.network()
        self.cluster = os.path.join(self.tmp, 'cluster')
        self.env = dict(os.environ, SLURM_CONF=os.path.join(self.cluster, 'slurm.conf'),
                        SLURM_TEST_PORT=str(16960 + os.getpid() % 30),
                        SLURM_SECOND_NODE='%s %s.1 %s.2' % (TAG, SUBNET, SUBNET))
        os.chmod(self.tmp, 0o755)  # munged runs as user munge: it must reach its folder
        start = subprocess.run([CLUSTER, 'start', self.cluster], env=self.env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=120)
        self.assertEqual(start.returncode, 0, start.stdout)
        self.assertIn('2 nodes idle', start.stdout)
        out = os.path.join(self.tmp, 'slurm')
        proc = subprocess.run(SWEEP + [write(self.tmp, 'tiny.yaml', TINY), '--out', out, '--slurm', '--chunk', '1'],
                              env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        same_tables(self, out, local)
        nodes = {}
        for log in glob.glob(os.path.join(out, 'slurm', '*.out')):
            with open(log) as f:
                for line in f:
                    if line.startswith('array task '):
                        nodes[line.split()[-1]] = nodes.get(line.split()[-1], 0) + 1
        self.assertEqual(sum(nodes.values()), 8, nodes)
        self.assertEqual(len(nodes), 2, 'both nodes ran array tasks: %s' % nodes)


if __name__ == '__main__':
    rosrun('swarm_forage', 'sshlogin_hosts', TwoHosts)
