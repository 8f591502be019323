#!/usr/bin/env python3
"""Writes an RViz configuration whose top-down view shows a whole drive: the template's view centre
(X, Y) and scale (pixels per metre) are replaced by ones that fit the drive's positions, with a margin
for the map around them, into the 3D view of RViz's 1400 x 900 window.

usage: demo_view.py POSES_TXT TEMPLATE_RVIZ OUT_RVIZ
POSES_TXT: KITTI-style poses (3 x 4 row-major per line) in the frame RViz shows (the odometry's)."""
import re
import sys

VIEW_PIXELS = (1000.0, 790.0)  # the 3D view of a 1400 x 900 window with the displays panel on the left
MARGIN_M = 60.0                # the keyframe clouds reach this far beside the path


def fitted_view(positions):
    xs = [p[0] for p in positions]
    ys = [p[1] for p in positions]
    width = max(xs) - min(xs) + 2.0 * MARGIN_M
    height = max(ys) - min(ys) + 2.0 * MARGIN_M
    scale = min(VIEW_PIXELS[0] / width, VIEW_PIXELS[1] / height)
    return (max(xs) + min(xs)) / 2.0, (max(ys) + min(ys)) / 2.0, scale


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    positions = []
    with open(argv[1]) as poses:
        for line in poses:
            values = [float(v) for v in line.split()]
            if len(values) != 12:
                sys.exit("%s: a pose line without 12 numbers" % argv[1])
            positions.append((values[3], values[7]))
    if not positions:
        sys.exit("%s: no poses" % argv[1])
    x, y, scale = fitted_view(positions)
    with open(argv[2]) as template:
        text = template.read()
    # The view block's keys are indented by six spaces; the only "Scale:", "X:" and "Y:" at that depth.
    for key, value in (("Scale", scale), ("X", x), ("Y", y)):
        text, count = re.subn(r"(?m)^(      %s: ).*$" % key, r"\g<1>%.2f" % value, text)
        if count != 1:
            sys.exit("%s: expected one view '%s:' line, found %d" % (argv[2], key, count))
    with open(argv[3], "w") as out:
        out.write(text)
    print("RViz view: centre (%.0f, %.0f) m, %.2f pixels per metre" % (x, y, scale))


if __name__ == "__main__":
    main(sys.argv)
