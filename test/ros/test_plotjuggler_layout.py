#!/usr/bin/env python3
"""rostest: the PlotJuggler layout (config/plotjuggler_layout.xml) against the
node's topics and message fields (PlotJuggler itself is not in Debian: the
layout file is what is tested)."""
import os
import unittest
import xml.etree.ElementTree as ET

import rospkg
import rostest
from rotor_rub_msgs.msg import ProbeSignals, RotorState

PKG = "rotor_rub_sim"
NS = "/rotor_rub_sim"  # sim.launch's default namespace
# The node's topics (docs/node.md) whose messages the layout plots.
TOPICS = {NS + "/state": RotorState, NS + "/probes": ProbeSignals}


def has_field(msg_type, path):
    """Whether msg_type has the nested field path ("rotor_position/x")."""
    value = msg_type()
    for part in path.split("/"):
        if part not in getattr(value, "__slots__", ()):
            return False
        value = getattr(value, part)
    return isinstance(value, (int, float, bool))


class PlotJugglerLayoutTest(unittest.TestCase):
    def test_every_curve_is_a_field_the_node_publishes(self):
        path = os.path.join(rospkg.RosPack().get_path(PKG), "config", "plotjuggler_layout.xml")
        root = ET.parse(path).getroot()
        self.assertEqual(root.tag, "root")
        names = []
        for curve in root.iter("curve"):
            names += [curve.get(k) for k in ("curve_x", "curve_y") if curve.get(k)] or [curve.get("name")]
        self.assertGreaterEqual(len(names), 10)
        for name in names:
            topic = next((t for t in TOPICS if name.startswith(t + "/")), None)
            self.assertIsNotNone(topic, name + ": not a topic of the node")
            self.assertTrue(has_field(TOPICS[topic], name[len(topic) + 1:]), name + ": no such numeric field")
        plotted = set(names)
        for needed in ("/state/rotor_position/x", "/state/normal_force", "/state/speed", "/probes/x"):
            self.assertIn(NS + needed, plotted)


if __name__ == "__main__":
    rostest.rosrun(PKG, "plotjuggler_layout", PlotJugglerLayoutTest)
