#!/usr/bin/python3
"""The haptic truth suite's rule for runs the machine disturbed (scripts/bench/haptic_truth.py,
docs/haptic_truth.md, Scheduling): a run that misses its goals is run again only when the server's states
stalled or the hypervisor stole over 5 % of the CPU time, after a quiet second, at most three runs; a miss on
an undisturbed machine stands at once. And the steal column is read from /proc/stat's aggregate line."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "bench"))
import cpu_steal  # noqa: E402
import haptic_truth  # noqa: E402

QUIET = {"oldest_state_ms": 3.0, "steal": 0.002}
STOLEN = {"oldest_state_ms": 19.1, "steal": 0.21}  # the CI run that failed tall_box_slide, hand, 0 ms
STALLED = {"oldest_state_ms": 25.0, "steal": 0.0}


class Runs:
    """run_once from a list of (result, missed its goals)."""

    def __init__(self, runs):
        self.runs, self.count, self.said, self.waits = list(runs), 0, [], 0

    def once(self):
        r, missed = self.runs[self.count]
        self.count += 1
        return dict(r, missed=missed), "log"

    def wait(self, threshold):
        self.waits += 1
        return 0.003

    def go(self, delay=0):
        return haptic_truth.run_until_judged(self.once, lambda r: ["off"] if r["missed"] else [], delay,
                                             lambda why, fails, quiet: self.said.append(why), wait=self.wait)


class RerunRule(unittest.TestCase):
    def test_a_run_that_meets_its_goals_is_run_once(self):
        runs = Runs([(STOLEN, False)])
        _, _, fails, attempts = runs.go()
        self.assertEqual((fails, attempts, runs.waits), ([], 1, 0))

    def test_a_miss_on_an_undisturbed_machine_stands(self):
        runs = Runs([(QUIET, True), (QUIET, False)])
        _, _, fails, attempts = runs.go()
        self.assertEqual((fails, attempts, runs.waits), (["off"], 1, 0))

    def test_a_miss_while_stolen_from_is_run_again_after_a_quiet_second(self):
        runs = Runs([(STOLEN, True), (QUIET, False)])
        _, _, fails, attempts = runs.go()
        self.assertEqual((fails, attempts, runs.waits), ([], 2, 1))
        self.assertIn("21 %", runs.said[0])

    def test_a_stall_then_a_theft_then_a_quiet_miss_fails(self):
        runs = Runs([(STALLED, True), (STOLEN, True), (QUIET, True)])
        _, _, fails, attempts = runs.go()
        self.assertEqual((fails, attempts), (["off"], 3))
        self.assertIn("stopped 25.0 ms", runs.said[0])

    def test_three_disturbed_misses_fail(self):
        runs = Runs([(STOLEN, True)] * 4)
        _, _, fails, attempts = runs.go()
        self.assertEqual((fails, attempts, runs.count), (["off"], haptic_truth.ATTEMPTS, 3))

    def test_in_process_runs_are_never_repeated(self):
        runs = Runs([(STOLEN, True), (QUIET, False)])
        _, _, fails, attempts = runs.go(delay=None)
        self.assertEqual((fails, attempts), (["off"], 1))

    def test_the_bounds_of_disturbance(self):
        # 20 ms beyond the path's delay stalls; 5 % of the CPU time stolen disturbs.
        self.assertIsNone(haptic_truth.machine_disturbed({"oldest_state_ms": 21.9, "steal": 0.05}, 2))
        self.assertIsNotNone(haptic_truth.machine_disturbed({"oldest_state_ms": 22.1, "steal": 0.0}, 2))
        self.assertIsNotNone(haptic_truth.machine_disturbed({"oldest_state_ms": 1.0, "steal": 0.051}, 20))


class StealColumn(unittest.TestCase):
    def test_the_eighth_figure_of_the_aggregate_line(self):
        with tempfile.NamedTemporaryFile("w", suffix=".stat") as f:
            f.write("cpu  4705 150 1120 16250 520 0 26 731 0 0\ncpu0 2000 75 560 8125 260 0 13 400 0 0\n")
            f.flush()
            self.assertEqual(cpu_steal.steal_ticks(f.name), 731)

    def test_a_kernel_without_the_column_reads_zero(self):
        with tempfile.NamedTemporaryFile("w", suffix=".stat") as f:
            f.write("cpu  4705 150 1120 16250\n")
            f.flush()
            self.assertEqual(cpu_steal.steal_ticks(f.name), 0)

    def test_this_machine_steals_a_share_between_0_and_1(self):
        share = cpu_steal.StealMeter().start()
        sum(range(200000))
        self.assertTrue(0.0 <= share.share() <= 1.0)


if __name__ == "__main__":
    unittest.main()
