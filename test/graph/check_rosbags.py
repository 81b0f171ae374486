#!/usr/bin/env python3
"""The reference runs of rosbags/ still give their expected metrics: run_tables over the folder
reproduces rosbags/expected_metrics.yaml, and each bag replayed with `rosbag play --clock` into a fresh
metrics_node (with the folder as its library) gives the expected P series, and e, Z, R, A live. A folder
with one damaged bag: run_tables names it and writes the other runs' tables."""
import csv
import glob
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rospkg
import rospy
import rostest
import yaml
from swarm_forage.msg import FlexibilityMetric, IntervalPerformance, ScalabilityMetric, SelfOrganizationMetric
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, until  # noqa: E402

REPLAYED = ['/world/run_info', '/world/performance', '/swarm/status', '/world/run_end']


def records(data, at, end):
    """The records of a bag's bytes [at, end): (position, header fields, data position, data length)."""
    while at < end:
        length = struct.unpack_from('<I', data, at)[0]
        fields, field = {}, at + 4
        while field < at + 4 + length:
            n = struct.unpack_from('<I', data, field)[0]
            name, _, value = data[field + 4:field + 4 + n].partition(b'=')
            fields[name.decode()] = value
            field += 4 + n
        size = struct.unpack_from('<I', data, at + 4 + length)[0]
        yield at, fields, at + 8 + length, size
        at += 8 + length + size


def index_entry(data, topic):
    """Where the first index entry of `topic` in a bag's bytes lies (the data of its index record)."""
    header = next(records(data, 13, len(data)))
    index_pos = struct.unpack('<Q', header[1]['index_pos'])[0]
    conns = {struct.unpack('<I', h['conn'])[0]: h['topic'].decode()
             for _, h, _, _ in records(data, index_pos, len(data)) if h['op'] == b'\x07'}
    first_chunk = header[2] + header[3]
    for _, h, data_at, _ in records(data, first_chunk, index_pos):
        if h['op'] == b'\x04' and conns[struct.unpack('<I', h['conn'])[0]].endswith(topic):
            return data_at
    raise AssertionError('no index of %s after the first chunk' % topic)


def near(a, b):
    return abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


class Collected:
    def __init__(self):
        self.msgs = {}
        for topic, kind in (('performance', IntervalPerformance), ('scalability', ScalabilityMetric),
                            ('self_organization', SelfOrganizationMetric), ('reactivity', FlexibilityMetric),
                            ('adaptability', FlexibilityMetric)):
            rospy.Subscriber('/replay/metrics/' + topic, kind, self.add, callback_args=topic, queue_size=10000)

    def add(self, msg, topic):
        self.msgs.setdefault(topic, []).append(msg)

    def final(self, topic):
        """The last final message of `topic`, waiting while the replayed metrics keep coming."""
        until(lambda: any(m.final for m in self.msgs.get(topic, [])),
              lambda: sum(map(len, self.msgs.values())), 'a final /replay/metrics/' + topic)
        return [m for m in self.msgs[topic] if m.final][-1]


class ReferenceBags(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_rosbags')
        cls.source = os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'rosbags')
        with open(os.path.join(cls.source, 'expected_metrics.yaml')) as f:
            cls.expected = yaml.safe_load(f)
        cls.library = removed_at_exit(rospy.get_param('~library'))
        os.makedirs(cls.library, exist_ok=True)
        for bag in glob.glob(os.path.join(cls.source, '*.bag')):
            shutil.copy(bag, cls.library)

    def test_1_run_tables_reproduce_the_expected_tables(self):
        out = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reference_tables_'))
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', self.source, 'out:=' + out,
                               'sample_interval:=%d' % self.expected['sample_interval']],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('5 runs in 5 groups', proc.stdout)
        for name in ('scalability', 'self_organization', 'flexibility'):
            with open(os.path.join(out, name + '.csv')) as f:
                valid = [r for r in csv.DictReader(f) if r['valid'] == '1']
            self.assertEqual(len(valid), len(self.expected[name]), name)
            for want in self.expected[name]:
                match = [r for r in valid if r['controller'] == want['controller'] and r['waveform'] == want['waveform']]
                self.assertEqual(len(match), 1, (name, want))
                for key, value in want.items():
                    if key not in ('controller', 'waveform'):
                        self.assertTrue(near(float(match[0][key]), value), (name, key, match[0][key], value))

    def replay(self, name):
        got = Collected()
        time.sleep(0.5)
        cmd = ['rosbag', 'play', '--clock', '--quiet', '-r', '500', '--queue=100000', '--wait-for-subscribers',
               os.path.join(self.source, name + '.bag'), '--topics'] + REPLAYED + \
              ['%s:=/replay%s' % (t, t) for t in REPLAYED]
        subprocess.run(cmd, check=True, timeout=180)
        return got

    def test_2_each_replay_gives_the_expected_series(self):
        for name, series in sorted(self.expected['runs'].items()):
            got = self.replay(name)
            got.final('performance')
            run = got.msgs['performance'][-1].run
            p = [m.P for m in got.msgs['performance'] if m.run == run]
            self.assertEqual(p, series, name)

    def test_3_replays_give_the_expected_metrics_live(self):
        got = self.replay('crw_32x16_n16_null')
        e, z = got.final('scalability'), got.final('self_organization')
        want_e, want_z = self.expected['scalability'][0], self.expected['self_organization'][0]
        self.assertTrue(e.valid, e.status)
        self.assertTrue(near(e.e, want_e['e']), (e.e, want_e))
        self.assertTrue(z.valid, z.status)
        self.assertTrue(near(z.Z_sum, want_z['Z_sum']), (z.Z_sum, want_z))
        got = self.replay('crw_32x16_n16_step_down0.4')
        want = self.expected['flexibility'][0]
        for topic, key in (('reactivity', 'R'), ('adaptability', 'A')):
            m = got.final(topic)
            self.assertTrue(m.valid, m.status)
            self.assertTrue(near(m.distance, want[key]), (topic, m.distance, want))


    def test_4_a_bag_copied_connection_by_connection_gives_the_same_tables(self):
        """Chunks out of time order (a checkpoint's copy): run_tables reads such a bag through a handle per
        per-tick topic (follower_messages), and must give the same tables, byte for byte, as the bags as recorded."""
        copies = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reference_copies_'))
        for path in glob.glob(os.path.join(self.source, '*.bag')):
            with rosbag.Bag(path) as bag, rosbag.Bag(os.path.join(copies, os.path.basename(path)), 'w',
                                                     chunk_threshold=4096) as out:
                info = bag.get_type_and_topic_info().topics
                for topic in sorted(info):
                    for _, msg, t, header in bag.read_messages(topics=[topic], raw=True,
                                                                return_connection_header=True):
                        out.write(topic, msg, t, raw=True, connection_header=header)
        tables = {}
        for name, folder in (('recorded', self.source), ('copied', copies)):
            out = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reference_tables_'))
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', folder, 'out:=' + out,
                                   'sample_interval:=%d' % self.expected['sample_interval'], 'bootstrap:=50'],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            tables[name] = {}
            for csv_path in sorted(glob.glob(os.path.join(out, '*.csv'))):
                with open(csv_path, 'rb') as f:
                    tables[name][os.path.basename(csv_path)] = f.read()
        self.assertEqual(sorted(tables['copied']), sorted(tables['recorded']))
        for name, data in tables['recorded'].items():
            self.assertEqual(tables['copied'][name], data, name)

    def test_5_a_bag_with_a_damaged_index_is_named_and_the_others_tabled(self):
        """One flipped byte in an index entry of world/performance (its offset now 1 GiB into its chunk) made
        rosbag read past its buffer; run_tables refuses that bag by name and writes the other four's tables."""
        folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reference_damaged_'))
        for path in glob.glob(os.path.join(self.source, '*.bag')):
            shutil.copy(path, folder)
        damaged = os.path.join(folder, 'crw_32x16_n16_null.bag')
        with open(damaged, 'r+b') as f:
            data = f.read()
            at = index_entry(data, 'world/performance') + 11  # entry 0: sec, nsec, offset; the offset's high byte
            f.seek(at)
            f.write(bytes([data[at] ^ 0x40]))
        out = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reference_tables_'))
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', folder, 'out:=' + out,
                               'sample_interval:=%d' % self.expected['sample_interval']],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn('run_tables: %s: not a whole bag: it has an index entry of connection' % damaged, proc.stderr)
        self.assertIn('4 runs in 4 groups', proc.stdout)
        with open(os.path.join(out, 'scalability.csv')) as f:
            rows = list(csv.DictReader(f))
        self.assertTrue(rows)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'rosbags', ReferenceBags)
