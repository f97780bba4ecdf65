#!/usr/bin/python3
"""The accuracy report (docs/accuracy/make_report.py) on small real inputs: the --quick outputs
of lighting_sweep and light_location_sweep, run here, and the frame-sweep fixture of
tests/report/fixtures/ (two scenes, numbers chosen so that each formatted figure is known:
OER's rows are the default's without occlusion, our default's occlude the residual map, and
forest has the transfer rule's check).

    make_report_test.py --lighting-sweep BIN --location-sweep BIN --work DIR

ctest runs it as the test `report` (label `report`).
"""

import argparse
import json
import shutil
import struct
import subprocess
import sys
import unittest
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
MAKE_REPORT = SOURCE / "docs" / "accuracy" / "make_report.py"
FIXTURE = SOURCE / "tests" / "report" / "fixtures"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
arguments = argparse.Namespace()


def run_report(frames: Path, out: Path) -> subprocess.CompletedProcess:
    """make_report.py on the quick sweeps and `frames`, as scripts/accuracy-report.sh runs it."""
    return subprocess.run(
        [sys.executable, str(MAKE_REPORT), "--lighting", str(arguments.work / "lighting.json"),
         "--location", str(arguments.work / "location.json"), "--frames", str(frames),
         "--out", str(out), "--shadows", str(FIXTURE / "shadow_sweep.json"),
         "--shadows-before", str(FIXTURE / "shadow_sweep_before.json")],
        capture_output=True, text=True, check=False)


class MakeReportTest(unittest.TestCase):
    """One report written from the fixture, read back by every test."""

    @classmethod
    def setUpClass(cls) -> None:
        work = arguments.work
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        for binary, name in ((arguments.lighting_sweep, "lighting"),
                             (arguments.location_sweep, "location")):
            subprocess.run([binary, "--quick", "--json", str(work / f"{name}.json"),
                            "--csv", str(work / f"{name}.csv")], check=True,
                           stdout=subprocess.DEVNULL)
        cls.out = work / "report"
        # An earlier run's figure of a world since dropped, which the report must not keep.
        cls.stale = cls.out / "accuracy" / "figures" / "frames-dropped.png"
        cls.stale.parent.mkdir(parents=True)
        cls.stale.write_bytes(PNG_SIGNATURE)
        result = run_report(FIXTURE, cls.out)
        if result.returncode != 0:
            raise AssertionError(f"make_report.py failed: {result.stderr}")
        cls.markdown = (cls.out / "accuracy.md").read_text(encoding="utf-8")

    def test_headline_rows_carry_the_fixture_figures(self) -> None:
        # forest's default, with occlusion: each mode's own frame, 24.6 ms in the none mode.
        self.assertIn("| forest | ours (default) | 6.0 % / −30.1 dB | 4.3 % / −32.0 dB | "
                      "7.5 % / −28.0 dB | 7.1 % / −29.0 dB | 5.3 % / −31.0 dB | "
                      "9.8 % / −27.0 dB | 24.6 | 0.18 | passes |", self.markdown)
        # forest's OER: 0.1234 / -24.56 dB, 0.0871 / -27.02 dB, ...; 21.34 ms; noise 0.12.
        self.assertIn("| forest | OER, no occlusion | 12.3 % / −24.6 dB | 8.7 % / −27.0 dB | "
                      "18.0 % / −20.0 dB | 15.0 % / −23.1 dB | 11.1 % / −25.4 dB | "
                      "21.0 % / −20.0 dB | 21.3 | 0.12 | passes |", self.markdown)
        # plain SH's one-bounce object comparison has noise_ratio 0.25: marked, and the footnote.
        self.assertIn("| forest | plain SH | 31.2 % / −17.2 dB | 28.4 % / −18.1 dB | "
                      "25.0 % / −20.0 dB | 35.5 % / −16.2 dB † | 30.1 % / −17.5 dB | "
                      "15.0 % / −20.0 dB | 6.7 | 0.25 | fails |", self.markdown)
        # The thesis has no ground-near rows: dashes in those columns.
        self.assertIn("| forest | thesis | 27.2 % / −19.3 dB | 33.0 % / −16.8 dB | — | "
                      "29.0 % / −18.6 dB | 35.8 % / −15.9 dB | — |", self.markdown)
        self.assertIn("does not meet the noise requirement", self.markdown)
        # night has no thesis rows: no line for it rather than a line of dashes.
        self.assertNotIn("| night | thesis |", self.markdown)

    def test_soft_shadows_rows_carry_before_and_now(self) -> None:
        # the bunny's penumbra: 28.1 % before, 14.6 % now; high-pass 0.0575 and 0.0370 over 0.0210.
        self.assertIn("## Soft shadows", self.markdown)
        self.assertIn("| bunny | default | 2 | 2048 | 3583 | 28.1 % | 14.6 % | 2.8 % | "
                      "0.0575 / 0.0210 = 2.74 | 0.0370 / 0.0210 = 1.76 |", self.markdown)
        self.assertIn("| dress form | default | 1 | 512 | 582 | 0.162 | 0.305 | 0.187 |",
                      self.markdown)

    def test_per_mesh_means_and_front(self) -> None:
        # means of 0.1234 and 0.0642; of 0.18 and 0.09 near the bunny; of 21.34 and 18.9 ms.
        self.assertIn("| bunny | OER, no occlusion | 2 | 9.4 % | 7.0 % | 13.5 % | −27.2 | 20.1 | "
                      "2 of 2 |", self.markdown)
        # forest's default (24.6 ms, 6.01 %) is on the front: 576 rays is more accurate but
        # slower. "lights 1" (15.5 ms, 11.11 %) beats OER (21.34 ms, 12.34 %) on the object
        # among the light counts, which vary OER; not on the ground.
        self.assertIn("| forest | on the front | on the front | "
                      "no: lights 1 (15.5 ms, 11.1 %) | on the front |", self.markdown)

    def test_occlusion_section_first_with_ratios_and_verdicts(self) -> None:
        section = self.markdown.index("## Occlusion of the residual map")
        self.assertLess(self.markdown.index("# Accuracy"), section)
        self.assertLess(section, self.markdown.index("## Headline"))
        # ours / plain SH: 0.0601 / 0.3125 on the product, 0.0752 / 0.25 near it.
        self.assertIn("| bunny | forest | none (direct reference) | 6.0 % | 31.2 % | 12.3 % | "
                      "0.19 | pass | 7.5 % | 25.0 % | 18.0 % | 0.30 | pass | 1234 | "
                      "24.6 / 21.3 |", self.markdown)
        # 0.098 / 0.15 near the bunny is above half: fail; plain SH's noisy row is marked.
        self.assertIn("| bunny | forest | one (one-bounce reference) | 7.1 % | 35.5 % † | "
                      "15.0 % | 0.20 | pass | 9.8 % | 15.0 % | 21.0 % | 0.65 | fail | 2345 | "
                      "25.8 / 21.3 |", self.markdown)
        # night's one-bounce product (0.13 / 0.2431) fails, its ground near passes.
        self.assertIn("holds on the product in 3 of 4 comparisons (ours/plain 0.19–0.53) and on "
                      "the ground near it in 3 of 4 comparisons (ours/plain 0.30–0.65).",
                      self.markdown)
        self.assertIn("transfer bakes in 2345 ms with one bounce and 1234 ms without, above the "
                      "target's 2000 ms", self.markdown)
        # 24.6 / 21.34, 25.8 / 21.34, 22.0 / 18.9, 23.0 / 18.9.
        self.assertIn("A frame with occlusion takes 1.15–1.22x the time of one without",
                      self.markdown)

    def test_rule_check_marks_the_rule_and_finds_the_knee(self) -> None:
        # forest's rig has order 7: the transfer is evaluated at 5.
        self.assertIn("| forest | **144 rays, order 5 (rig order 7): the rule** | 1234 / 2345 | "
                      "6.0 % | 7.1 % | 7.5 % | 9.8 % | 24.6 |", self.markdown)
        self.assertIn("| forest | 576 rays, order 5 (rig order 7) | 4800 / 9100 | 5.9 % | 7.0 % | "
                      "7.4 % | 9.5 % | 24.7 |", self.markdown)
        self.assertIn("| forest | 144 rays, order 3 | 1234 / 2345 | 6.5 % | 7.6 % | 8.0 % | "
                      "10.0 % | 23.0 |", self.markdown)
        self.assertNotIn("| night | **144 rays", self.markdown)
        # 64 rays are more than 5 % worse than the best everywhere, 144 within 5 % of it.
        self.assertIn("the rule's choice sits at the knee. Fewer rays change the error by +0.90 "
                      "to +1.48 points (positive: worse); the most rays checked improve it by "
                      "+0.10 to +0.30 points at 3.9x the bake time. With the rig at order 3 "
                      "instead of its own (7; the transfer is evaluated at the rig's order, at "
                      "most the bake's, `kTransferBakeOrder`), the error changes by +0.20 to +0.50 points.", self.markdown)

    def test_lighting_tables_carry_the_sweep_figures(self) -> None:
        lighting = json.loads((arguments.work / "lighting.json").read_text(encoding="utf-8"))
        rows = [row for row in lighting["rows"] if row["world"] == "city" and row["order"] == 3
                and row["window"] == "none" and row["downsampling"] == 1]
        whole = next(row for row in rows if all(row["lights_on"]))["relative_rms"]
        worst = max(row["relative_rms"] for row in rows)
        self.assertIn(f"{100 * whole:.2f} % / {100 * worst:.2f} %", self.markdown)
        self.assertIn("**SH truncation.** At order 3", self.markdown)
        # The fixture's hard shadows: forest +0.67 / +0.41 points, night +0.08 / +0.11.
        self.assertIn("change the bunny's error by +0.1 points to +0.7 points (mean +0.4 points) "
                      "on the object and by +0.1 points to +0.4 points (mean +0.3 points) on the "
                      "ground over 2 worlds", self.markdown)
        self.assertIn("its frame time by −2.3 to −1.7 ms.", self.markdown)
        self.assertIn("| pair_3deg | default | 1024x512 | 1 for 2 |", self.markdown)

    def test_figures_are_png_files(self) -> None:
        for name in ("frames-forest.png", "frames-night.png", "lighting-orders.png",
                     "transfer-rule.png"):
            data = (self.out / "accuracy" / "figures" / name).read_bytes()
            self.assertEqual(data[:8], PNG_SIGNATURE, name)
            self.assertGreater(len(data), 10_000, name)
            self.assertIn(f"(accuracy/figures/{name})", self.markdown)
        self.assertFalse(self.stale.exists())

    def test_side_by_side_images_are_copied(self) -> None:
        copied = self.out / "accuracy" / "images" / "bunny-forest-error-default.png"
        self.assertEqual(copied.read_bytes(),
                         (FIXTURE / "images" / "bunny-forest-error-default.png").read_bytes())
        self.assertIn('<img src="accuracy/images/bunny-night-default.png"', self.markdown)
        # night's fixture has no plain SH image: its cell is a dash.
        self.assertRegex(self.markdown, r"\| bunny, night \| <img[^|]*\| — \| <img")

    def test_missing_field_names_it_and_exits_1(self) -> None:
        broken = arguments.work / "broken-field"
        shutil.copytree(FIXTURE, broken, dirs_exist_ok=True)
        document = json.loads((broken / "frame_sweep.json").read_text(encoding="utf-8"))
        del document["rows"][5]["relative_rms"]
        (broken / "frame_sweep.json").write_text(json.dumps(document), encoding="utf-8")
        result = run_report(broken, arguments.work / "broken-report")
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn(f"{broken / 'frame_sweep.json'}: rows[5]: missing field 'relative_rms'",
                      result.stderr)

    def test_null_figure_names_it_and_exits_1(self) -> None:
        broken = arguments.work / "broken-null"
        shutil.copytree(FIXTURE, broken, dirs_exist_ok=True)
        document = json.loads((broken / "frame_sweep.json").read_text(encoding="utf-8"))
        document["rows"][2]["fidelity_db"] = None  # how nlohmann::json writes a NaN
        (broken / "frame_sweep.json").write_text(json.dumps(document), encoding="utf-8")
        result = run_report(broken, arguments.work / "broken-report")
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn("rows[2]: field 'fidelity_db' is null, expected a finite number",
                      result.stderr)

    def test_images_sharing_a_name_are_refused(self) -> None:
        broken = arguments.work / "broken-names"
        shutil.copytree(FIXTURE, broken, dirs_exist_ok=True)
        (broken / "other").mkdir(exist_ok=True)
        shutil.copyfile(broken / "images" / "bunny-forest-default.png",
                        broken / "other" / "bunny-night-default.png")
        document = json.loads((broken / "frame_sweep.json").read_text(encoding="utf-8"))
        document["scenes"][1]["images"]["plain_sh"] = "other/bunny-night-default.png"
        (broken / "frame_sweep.json").write_text(json.dumps(document), encoding="utf-8")
        result = run_report(broken, arguments.work / "broken-report")
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn("share the name bunny-night-default.png", result.stderr)

    def test_missing_image_names_it_and_exits_1(self) -> None:
        broken = arguments.work / "broken-image"
        shutil.copytree(FIXTURE, broken, dirs_exist_ok=True)
        (broken / "images" / "bunny-night-reference.png").unlink()
        result = run_report(broken, arguments.work / "broken-report")
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn("scenes[1].images.reference: no file", result.stderr)
        self.assertIn("bunny-night-reference.png", result.stderr)


GLMARK2_HORSE = Path("/usr/share/glmark2/models/horse.3ds")
ASSIMP = shutil.which("assimp")
UPRIGHT_GLB = SOURCE / "docs" / "accuracy" / "upright_glb.py"


@unittest.skipUnless(GLMARK2_HORSE.is_file() and ASSIMP,
                     "needs glmark2-data and assimp-utils (scripts/setup-debian.sh "
                     "--with-test-data)")
class UprightGlbTest(unittest.TestCase):
    """upright_glb.py on assimp's glTF binary of glmark2's horse, as accuracy-report.sh runs it."""

    def test_removes_the_axis_conversion_and_keeps_the_rest(self) -> None:
        arguments.work.mkdir(parents=True, exist_ok=True)
        converted = arguments.work / "horse-assimp.glb"
        upright = arguments.work / "horse.glb"
        subprocess.run([ASSIMP, "export", str(GLMARK2_HORSE), str(converted)], check=True,
                       stdout=subprocess.DEVNULL)
        subprocess.run([sys.executable, str(UPRIGHT_GLB), str(converted), str(upright)],
                       check=True)
        before, after = converted.read_bytes(), upright.read_bytes()
        header = struct.Struct("<IIIII")
        _, _, total, json_length, _ = header.unpack_from(after)
        self.assertEqual(total, len(after))
        self.assertEqual(json_length % 4, 0)
        root = json.loads(after[header.size:header.size + json_length])["nodes"][0]
        self.assertEqual(root["name"], "<3DSDummyRoot>")
        self.assertNotIn("matrix", root)
        # The BIN chunk (the geometry) is byte for byte assimp's.
        _, _, _, old_json_length, _ = header.unpack_from(before)
        self.assertEqual(after[header.size + json_length:],
                         before[header.size + old_json_length:])
        # A second pass finds no conversion to remove: refused, not silently passed through.
        again = subprocess.run([sys.executable, str(UPRIGHT_GLB), str(upright),
                                str(arguments.work / "horse-again.glb")],
                               capture_output=True, text=True, check=False)
        self.assertEqual(again.returncode, 1)
        self.assertIn("not assimp's 3ds axis conversion", again.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--lighting-sweep", required=True)
    parser.add_argument("--location-sweep", required=True)
    parser.add_argument("--work", type=Path, required=True)
    arguments, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest])
