"""Tests of the measurement scripts' parsing: both symbol manglings, missing symbols and lines, the
expectations comparison. Run: python3 -m unittest discover -s scripts/measure"""

import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(__file__))
import cost  # noqa: E402
import expect  # noqa: E402
import footprint  # noqa: E402
import pico_cost  # noqa: E402

LEGACY = [
    (170, "t", "firmware::runtime::Runtime$LT$P$C$E$C$_$C$_$C$_$C$_$GT$::apply::h6306e7a570cfb011"),
    (482, "t", "firmware::runtime::Runtime$LT$P$C$E$C$_$C$_$C$_$C$_$GT$::decide::h67441ecbd6114e8b"),
    (142, "t", "firmware::choice::Bits$LT$E$GT$::below::h2bda4ee22e62a863"),
    (226, "t", "_$LT$cell_qemu..UartPort$u20$as$u20$firmware..link..Port$GT$::note::h0000000000000000"),
    (64, "t", "_$LT$firmware..choice..RandomLocalQueue$LT$_$C$_$GT$$u20$as$u20$firmware..choice..Policy$LT$_$GT$$GT$::pick::h0123456789abcdef"),
    (1468, "r", "cell_qemu::tables::SECTIONS::h8b3def0d45d07b34"),
    (184, "r", "cell_qemu::tables::EVENT_NAMES::h41307687f48a4134"),
    (120, "b", "cell_qemu::app::__rtic_internal_local_resource_runtime::hcb52ffcd8913d1f3"),
]
V0 = [
    (170, "t", "<firmware::runtime::Runtime<firmware::choice::RandomLocalQueue<1, 3>, firmware::rng::SeedEntropy, 1, 10, false, 3>>::apply"),
    (482, "t", "<firmware::runtime::Runtime<firmware::choice::RandomLocalQueue<1, 3>, firmware::rng::SeedEntropy, 1, 10, false, 3>>::decide::<<firmware::link::Link>::service<firmware::choice::RandomLocalQueue<1, 3>, cell_qemu::UartPort>::{closure#0}>"),
    (142, "t", "<firmware::choice::Bits<firmware::rng::SeedEntropy>>::below"),
    (226, "t", "<cell_qemu::UartPort as firmware::link::Port>::note"),
    (64, "t", "<firmware::choice::RandomLocalQueue<1, 3> as firmware::choice::Policy<1>>::pick"),
    (1468, "r", "cell_qemu::tables::SECTIONS"),
    (184, "r", "cell_qemu::tables::EVENT_NAMES"),
    (120, "b", "cell_qemu::app::__rtic_internal_local_resource_runtime"),
]


def summary(symbols):
    kinds = footprint.classify(symbols)
    return {k: sorted((s, footprint.last_segment(n)) for s, n in v) for k, v in kinds.items()}


class Footprint(unittest.TestCase):
    def test_both_manglings_give_the_same_figures(self):
        legacy, v0 = summary(LEGACY), summary(V0)
        self.assertEqual(legacy, v0)
        self.assertEqual(legacy["code"], [(64, "pick"), (142, "below"), (170, "apply"), (482, "decide")])
        self.assertEqual(legacy["tables"], [(1468, "SECTIONS")])
        self.assertEqual(legacy["names"], [(184, "EVENT_NAMES")])
        self.assertEqual(legacy["runtime RAM"], [(120, "__rtic_internal_local_resource_runtime")])

    def test_state_tables_and_the_state_runtime_are_counted(self):
        symbols = [
            (82, "t", "<firmware::state::StateRuntime<firmware::choice::Random, firmware::rng::SeedEntropy, 1, 4> as firmware::runtime::Decide>::apply"),
            (280, "t", "_$LT$firmware..state..StateRuntime$LT$P$C$E$C$_$C$_$GT$$u20$as$u20$firmware..runtime..Decide$GT$::decide::h0123456789abcdef"),
            (64, "r", "cell_qemu::tables::CUBES"),
            (56, "r", "cell_qemu::tables::TABLES"),
            (44, "r", "cell_qemu::tables::SIGNAL_NAMES"),
        ]
        got = summary(symbols)
        self.assertEqual(got["code"], [(82, "apply"), (280, "decide")])
        self.assertEqual(got["tables"], [(56, "TABLES"), (64, "CUBES")])
        self.assertEqual(got["names"], [(44, "SIGNAL_NAMES")])

    def test_interface_code_is_not_runtime_code(self):
        names = [n for _, n in footprint.classify(V0)["code"]]
        self.assertFalse(any("UartPort" in n and "note" in n for n in names), names)


class Cost(unittest.TestCase):
    GOOD = """calibration: 2000 instructions = 3201 ticks
uncontrollable event (apply): n=9906 avg=266 ticks (~166 instructions) max=398 ticks (~248 instructions)
controllable decision (enabled + choose + guard + fire): n=4928 avg=513 ticks (~320 instructions) max=833 ticks (~520 instructions)
  enabled set alone: n=4928 avg=80 ticks (~49 instructions) max=81 ticks (~50 instructions)
decision with nothing enabled: n=5166 avg=98 ticks (~61 instructions) max=99 ticks (~61 instructions)
events in 9906, commands out 4928, unexpected 0
"""

    def test_figures(self):
        self.assertEqual(cost.parse(self.GOOD), {"apply.avg": 166, "apply.max": 248, "decide.avg": 320,
                                                 "decide.max": 520, "enabled.avg": 49, "idle_decide.avg": 61})

    def test_a_missing_line_fails(self):
        text = "\n".join(l for l in self.GOOD.splitlines() if "apply" not in l)
        with self.assertRaises(SystemExit) as e:
            cost.parse(text)
        self.assertIn("uncontrollable event (apply)", str(e.exception.code))

    def test_a_wrong_calibration_fails(self):
        with self.assertRaises(SystemExit):
            cost.parse(self.GOOD.replace("3201 ticks", "2000 ticks"))


class PicoCost(unittest.TestCase):
    @staticmethod
    def call(calls, avg, mx):
        return {"calls": calls, "avg_cycles": avg * 1.5, "max_cycles": mx * 2, "avg_instructions": avg,
                "max_instructions": mx}

    def report(self, **board):
        cost_ = {"apply": self.call(11000, 340, 499), "decision": self.call(8800, 574, 1003),
                 "idle_decision": self.call(9000, 61, 61), "redecision": self.call(0, 0, 0)}
        return {"target": "rp2040", "violations": 0, "board": {"hidden_commands": 0, "missed": 0, "cost": cost_, **board}}

    def test_figures(self):
        f = pico_cost.parse(self.report())
        self.assertEqual((f["apply.avg"], f["apply.max"], f["decide.avg"], f["decide.max"]), (340, 499, 574, 1003))
        self.assertEqual((f["apply.cycles.avg"], f["decide.cycles.max"], f["idle_decide.avg"]), (510, 2006, 61))
        self.assertNotIn("idle_decide.max", f)

    def test_a_qemu_report_or_a_broken_run_fails(self):
        with self.assertRaises(SystemExit):
            pico_cost.parse({"target": "qemu", "board": None})
        with self.assertRaises(SystemExit) as e:
            pico_cost.parse(self.report(hidden_commands=2))
        self.assertIn("2 hidden commands", str(e.exception.code))
        bad = self.report()
        bad["board"]["cost"]["decision"]["calls"] = 0
        with self.assertRaises(SystemExit):
            pico_cost.parse(bad)

    def test_an_image_linked_for_another_chip_fails(self):
        pico = [(".vector_table", 0x1000_0100, 192), (".boot2", 0x1000_0000, 256), (".text", 0x1000_01C0, 9572),
                (".data", 0x2000_0000, 60), (".bss", 0x2000_003C, 88), (".uninit", 0x2000_0094, 1308)]
        pico_cost.check_memory("cell-pico", pico)
        self.assertEqual(pico_cost.footprint(pico), {"flash": 10080, "static_ram": 1456})
        lm3s = [(".vector_table", 0, 192), (".text", 0xC0, 9280), (".boot2", 0x32C0, 256), (".data", 0x2000_0000, 60)]
        with self.assertRaises(SystemExit) as e:
            pico_cost.check_memory("cell-pico", lm3s)
        self.assertIn("not linked for the RP2040", str(e.exception.code))
        with self.assertRaises(SystemExit):
            pico_cost.check_memory("cell-pico", pico + [(".stray", 0x2010_0000, 4)])


class Expectations(unittest.TestCase):
    def check(self, text, measured):
        with tempfile.NamedTemporaryFile("w", suffix=".size", delete=False) as f:
            f.write(text)
        try:
            expect.check(f.name, measured)
        finally:
            os.unlink(f.name)

    def test_within_tolerance_passes(self):
        self.check("code 100 5%\ntables 50 0 <= 60\n", {"code": 104, "tables": 50})

    def test_drift_missing_new_and_goal_fail(self):
        for measured in ({"code": 106, "tables": 50}, {"code": 100}, {"code": 100, "tables": 50, "x": 1}):
            with self.assertRaises(SystemExit, msg=measured):
                self.check("code 100 5%\ntables 50 0\n", measured)
        with self.assertRaises(SystemExit):
            self.check("tables 50 20% <= 55\n", {"tables": 58})

    def test_rewrite_keeps_columns_comments_tolerances_and_goals(self):
        text = "# sizes\ncode     100   5%   <= 120  # the runtime\ntables   50    0\nnames 7 0\n"
        with tempfile.NamedTemporaryFile("w", suffix=".size", delete=False) as f:
            f.write(text)
        try:
            expect.rewrite(f.name, {"code": 98, "tables": 1524, "names": 9})
            with open(f.name, encoding="utf-8") as g:
                self.assertEqual(g.read(), "# sizes\ncode     98    5%   <= 120  # the runtime\n"
                                           "tables   1524  0\nnames 9 0\n")
        finally:
            os.unlink(f.name)


if __name__ == "__main__":
    unittest.main()
