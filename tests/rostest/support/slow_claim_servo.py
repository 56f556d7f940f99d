#!/usr/bin/python3
"""slow_claim_servo.py: scripts/py_servo_controller.py whose claims are held
back for `~claim_delay` wall seconds (read at each ~enable; default 1) after
each ~enable, for protocol_rig_slow_claim.test. Its ~enable answers "not claimed yet" and its
own retries claim the axes later, as a controller on a busy machine (or one
whose claim answer was lost) may: test_protocol_node must not start the stage
before dem_node lists the claim, or the stage's first ticks run open loop.
"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "..", "scripts"))

import rospy  # noqa: E402
import py_servo_controller as pysc  # noqa: E402


class SlowClaimServo(pysc.PyServoController):
    def __init__(self):
        self.delay = 0.0
        self.not_before = 0.0
        super().__init__()

    def on_enable(self, rq):
        with self.lock:
            self.delay = float(rospy.get_param("~claim_delay", 1.0))
            self.not_before = time.monotonic() + self.delay
        return super().on_enable(rq)

    def try_claim(self):
        if time.monotonic() < self.not_before:
            return "held back by the test for %g s (~claim_delay)" % self.delay
        return super().try_claim()


if __name__ == "__main__":
    rospy.init_node("servo")
    SlowClaimServo()
    rospy.spin()
