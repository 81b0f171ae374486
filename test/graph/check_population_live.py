#!/usr/bin/env python3
"""Population dynamics in a live realtime graph: world/population every tick; /diagnostics of world_node
gives the active count; world/markers hides the dead, greys the robots awaiting repair and writes the
queue; the rates change by dynamic_reconfigure (a bad one is refused with the reason and changes nothing),
and from the tick of a change on world/population carries the new rates and `changed`, which metrics_node
follows: it says the run is no reference from that tick on."""
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Log
from swarm_forage.msg import Population
from visualization_msgs.msg import MarkerArray

N = 40


class PopulationLive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_population_live')
        cls.population, cls.markers, cls.world_status, cls.log = [], [], [], []
        rospy.Subscriber('/rosout', Log, lambda m: cls.log.append(m.msg), queue_size=1000)
        rospy.Subscriber('world/population', Population, cls.population.append, queue_size=100000)
        rospy.Subscriber('world/markers', MarkerArray, cls.markers.append, queue_size=10)
        rospy.Subscriber('/diagnostics', DiagnosticArray, cls.on_diagnostics, queue_size=100)

    @classmethod
    def on_diagnostics(cls, msg):
        cls.world_status += [s for s in msg.status if s.name == 'world: stepping']

    def wait(self, what, predicate, timeout=300):
        end = time.time() + timeout
        while time.time() < end and not rospy.is_shutdown():
            if predicate():
                return
            time.sleep(0.1)
        self.fail('timed out waiting for ' + what)

    def test_live(self):
        self.wait('robots awaiting repair', lambda: self.population and self.population[-1].queue > 0)
        p = self.population[-1]
        self.assertFalse(p.changed)
        self.assertEqual((p.death, p.birth, p.malfunction, p.repair), (0.002, 0.0, 0.05, 0.01))
        self.assertEqual(p.present + (N - p.present), N)
        self.assertEqual(p.active + p.queue, p.present)

        # /diagnostics: world_node's status has the counts.
        self.wait('world diagnostics with the active count',
                  lambda: any(v.key == 'active robots' for s in self.world_status for v in s.values))
        values = {v.key: v.value for v in self.world_status[-1].values}
        self.assertTrue(0 <= int(values['active robots']) <= N, values)
        self.assertIn('robots awaiting repair', values)

        # Markers: the queue's robots grey (robots, id 4), the dead hidden, and the text.
        def queue_drawn():
            if not self.markers:
                return False
            by = {(m.ns, m.id): m for m in self.markers[-1].markers}
            return ('robots', 4) in by and by[('robots', 4)].points and ('population', 0) in by
        self.wait('markers of robots awaiting repair', queue_drawn)
        by = {(m.ns, m.id): m for m in self.markers[-1].markers}
        self.assertTrue(by[('population', 0)].text.startswith('active '), by[('population', 0)].text)
        self.assertIn('repair queue', by[('population', 0)].text)
        drawn = sum(len(m.points) for (ns, _), m in by.items() if ns == 'robots')
        self.assertLessEqual(drawn, N)  # the dead are not drawn

        # Live rates: a bad value is refused whole with the reason; a good one is applied from a tick on.
        client = dynamic_reconfigure.client.Client('/world/population', timeout=30)
        self.assertEqual(client.get_configuration(timeout=10)['last_change'], 'start-up parameters')
        cfg = client.update_configuration({'death': -0.5, 'repair': 0.2})
        self.assertTrue(cfg['last_change'].startswith('refused: '), cfg['last_change'])
        self.assertIn('population/death must be a rate per tick in [0, 1]', cfg['last_change'])
        self.assertEqual((cfg['death'], cfg['repair']), (0.002, 0.01))
        time.sleep(0.5)
        self.assertFalse(any(m.changed for m in self.population), 'a refused change changes nothing')
        cfg = client.update_configuration({'repair': 0.2})
        self.assertEqual(cfg['last_change'], 'applied')
        self.wait('world/population with the new rate', lambda: self.population[-1].repair == 0.2)
        changed = [m for m in self.population if m.changed]
        self.assertTrue(changed and changed[0].repair == 0.2)
        self.assertTrue(all(m.changed for m in self.population if m.tick >= changed[0].tick))
        said = 'a population rate was changed live at tick %d' % changed[0].tick
        self.wait('metrics_node saying the run is no reference', lambda: any(said in m for m in self.log))
        print('changed at tick %d; %d active, %d awaiting repair' % (changed[0].tick, self.population[-1].active,
                                                                    self.population[-1].queue))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'population_live', PopulationLive)
