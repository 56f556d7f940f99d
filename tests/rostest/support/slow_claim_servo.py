#!/usr/bin/python3
"""slow_claim_servo.py: scripts/py_servo_controller.py made to claim badly,
for protocol_rig_slow_claim.test. Read at each ~enable that follows a
~disable (the protocol node's order at every servo stage):
  ~claim_delay         1.0  wall seconds the claims are held back: ~enable
                            answers "not claimed yet", as a servo on a busy
                            machine may, and the servo's own retries claim later
  ~lost_claim_answers  0    the answers of that many claim_axes calls are
                            lost after dem_node ran them (ros/ros_comm#1976,
                            as on CI on 2026-12-05): the servo is told "failed"
test_protocol_node must start a stage only once the servo holds its axes,
or the stage's first ticks run open loop (other bits than triax_run's).
"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "..", "scripts"))

import rospy  # noqa: E402
import py_servo_controller as pysc  # noqa: E402


class LosingProxy:
    """A claim_axes proxy whose next `lose` answers are lost after the call."""

    def __init__(self, proxy):
        self.proxy = proxy
        self.lose = 0

    def __call__(self, **request):
        answer = self.proxy(**request)
        if self.lose > 0:
            self.lose -= 1
            raise rospy.ServiceException("answer lost on purpose (~lost_claim_answers)")
        return answer


class SlowClaimServo(pysc.PyServoController):
    def __init__(self):
        self.delay = 0.0
        self.not_before = 0.0
        super().__init__()
        with self.lock:
            self.claim_srv = LosingProxy(self.claim_srv)

    def on_enable(self, rq):
        with self.lock:
            if not self.enabled:
                self.delay = float(rospy.get_param("~claim_delay", 1.0))
                self.not_before = time.monotonic() + self.delay
                self.claim_srv.lose = int(rospy.get_param("~lost_claim_answers", 0))
        return super().on_enable(rq)

    def try_claim(self):
        if time.monotonic() < self.not_before:
            return "held back by the test for %g s (~claim_delay)" % self.delay
        return super().try_claim()


if __name__ == "__main__":
    rospy.init_node("servo")
    SlowClaimServo()
    rospy.spin()
