"""The report's motion: analysis/animate.py (GIFs of run folders) and analysis/report_html.py
(REPORT.md as a page with the viewers beside the figures), on small hand-written run folders.

animate: every view is a right-handed screen frame with z up (a rig is drawn upright); the
shared timeline shows each run's last frame at or before each instant; a two-run GIF has the
frames asked for and both runs' colours; a bone past its limit by more than 0.1 deg, and only
then, is drawn in the highlight colour; --experiment reads runs/order.txt.
report_html: text from summary files is escaped (a hostile name stays text); a link is made only
to a relative path or http(s); a row of figures with a view.html gets the viewer in an iframe
and the GIF left out; without one, the GIF stays.
"""
import colorsys
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import animate  # noqa: E402
import report_html  # noqa: E402

BONES = ("a", "b")


def write_run(folder, times, tip_x, excess=0.0):
    """A two-bone run folder: bone a from (0,0,0) to (0,0,1), bone b from there to (x,0,1) with
    x from tip_x per frame; excess (rad) on bone b's joint in every frame."""
    os.makedirs(folder)
    scene = {"rig": {"name": "two", "bones": [
        {"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1], "radius": 0.1},
        {"name": "b", "parent": "a", "head": [0, 0, 1], "tail": [1, 0, 1], "radius": 0.1}]},
        "control_points": [{"name": "tip", "bone": "b", "alpha": 1.0, "target": [1, 0, 1]}]}
    with open(os.path.join(folder, "scene.json"), "w") as f:
        json.dump(scene, f)
    cols = ["%s.%s_%s" % (b, e, a) for b in BONES for e in ("head", "tail") for a in "xyz"]
    limits = ["%s.limit_excess_%s" % (b, a) for b in BONES for a in "xyz"]
    with open(os.path.join(folder, "trajectory.csv"), "w") as t, \
            open(os.path.join(folder, "targets_and_limits.csv"), "w") as g:
        t.write(",".join(["step", "time"] + cols) + "\n")
        g.write(",".join(["step", "tip.target_x", "tip.target_y", "tip.target_z"] + limits) + "\n")
        for k, (time, x) in enumerate(zip(times, tip_x)):
            t.write(",".join(map(str, [k, time, 0, 0, 0, 0, 0, 1, 0, 0, 1, x, 0, 1])) + "\n")
            g.write(",".join(map(str, [k, 1, 0, 1, 0, 0, 0, 0, excess, 0])) + "\n")
    return folder


def gif_colours(path):
    """The GIF's frame count and {RGB colour: pixels summed over its frames}."""
    from PIL import Image
    im, seen = Image.open(path), {}
    for k in range(im.n_frames):
        im.seek(k)
        for n, c in im.convert("RGB").getcolors(1 << 20):
            seen[c] = seen.get(c, 0) + n
    return im.n_frames, seen


def near(colours, hex_colour, tol=12, least=50):
    """Whether at least `least` saturated pixels have hex_colour's hue (within tol degrees):
    drawing over white with some transparency and the GIF's palette keep the hue."""
    def hue_sat(rgb):
        h, _, s = colorsys.rgb_to_hls(*(c / 255 for c in rgb))
        return 360 * h, s
    want, _ = hue_sat([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)])
    count = 0
    for c, n in colours.items():
        h, sat = hue_sat(c)
        if sat > 0.3 and min(abs(h - want), 360 - abs(h - want)) <= tol:
            count += n
    return count >= least


class AnimateTest(unittest.TestCase):
    def test_views_are_right_handed_and_upright(self):
        for name, (right, up, back) in animate.VIEWS.items():
            cross = (right[1] * up[2] - right[2] * up[1], right[2] * up[0] - right[0] * up[2],
                     right[0] * up[1] - right[1] * up[0])
            for c, b in zip(cross, back):
                self.assertAlmostEqual(c, b, places=9, msg=name)
            low, high = animate._project((0, 0, 0), name), animate._project((0, 0, 1), name)
            self.assertGreater(high[1], low[1] + 0.5, name)  # z up is up on the screen

    def test_the_timeline_shows_each_runs_last_frame_at_or_before(self):
        runs = [{"times": [0.0, 1.0, 2.0]}, {"times": [0.0, 0.5, 1.5, 4.0]}]
        instants, picks = animate.timeline(runs, 5)
        self.assertEqual(instants, [0.0, 1.0, 2.0, 3.0, 4.0])
        self.assertEqual(picks, [[0, 1, 2, 2, 2], [0, 1, 2, 2, 3]])

    def test_two_runs_in_their_colours_and_no_highlight_within_limits(self):
        with tempfile.TemporaryDirectory() as d:
            one = write_run(os.path.join(d, "one"), [0, 1, 2], [1, 0.8, 0.6])
            two = write_run(os.path.join(d, "two"), [0, 1, 2], [1, 0.7, 0.2], excess=1e-4)
            frames, seen = gif_colours(animate.animate([one, two], os.path.join(d, "x.gif"),
                                                       "front", frames=7))
        self.assertEqual(frames, 7)
        self.assertTrue(near(seen, animate.PALETTE[0]) and near(seen, animate.PALETTE[1]))
        self.assertFalse(near(seen, animate.HIGHLIGHT))  # 1e-4 rad is under 0.1 deg

    def test_a_bone_past_its_limit_is_highlighted(self):
        with tempfile.TemporaryDirectory() as d:
            run = write_run(os.path.join(d, "bent"), [0, 1], [1, 0.5], excess=0.2)
            _, seen = gif_colours(animate.animate([run], os.path.join(d, "x.gif"), frames=2))
        self.assertTrue(near(seen, animate.HIGHLIGHT))

    def test_an_experiment_folder(self):
        with tempfile.TemporaryDirectory() as d:
            for name in ("p", "q"):
                write_run(os.path.join(d, "runs", name), [0, 1], [1, 0.5])
            with open(os.path.join(d, "runs", "order.txt"), "w") as f:
                f.write("q\np\n")
            animate.main([d, "--experiment", "--frames", "3"])
            frames, seen = gif_colours(os.path.join(d, "animation.gif"))
        self.assertEqual(frames, 3)
        self.assertTrue(near(seen, animate.PALETTE[1]))


HOSTILE = "</script><img src=x onerror=alert(1)>"


class ReportHtmlTest(unittest.TestCase):
    def test_text_is_escaped_and_only_safe_links(self):
        page = report_html.to_html("# %s\n\n- a **b** `c` [v](x/view.html) [j](javascript:f())\n"
                                   "\n| %s | y |\n|---|---|\n| 1 | 2 |\n" % (HOSTILE, HOSTILE))
        self.assertNotIn("<img src=x", page)
        self.assertEqual(page.count("&lt;/script&gt;&lt;img src=x onerror=alert(1)&gt;"), 2)
        self.assertIn('<a href="x/view.html">v</a>', page)
        self.assertNotIn('href="javascript', page)
        self.assertIn("<strong>b</strong> <code>c</code>", page)
        self.assertIn("<th>y</th>", page)

    def test_figures_beside_the_viewer(self):
        md = "## e\n\n![p.png](e/p.png)\n![e: animation](e/animation.gif)\n"
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "e"))
            without = report_html.to_html(md, d)
            open(os.path.join(d, "e", "view.html"), "w").close()
            beside = report_html.to_html(md, d)
        self.assertIn('src="e/animation.gif"', without)
        self.assertNotIn("<iframe", without)
        self.assertIn('<iframe src="e/view.html"', beside)
        self.assertIn('src="e/p.png"', beside)
        self.assertNotIn("animation.gif", beside)


if __name__ == "__main__":
    unittest.main()
