#!/usr/bin/env python3
"""Writes outline-panel-2000.kerf: an 18 mm panel whose outline is a wavy
ellipse of 2000 points (300 x 150 mm), a profile long enough that visiting
every edge at every sample dominates an export (docs/benchmarks.md)."""
import json
import math
import sys

n = 2000
points = [[round(150 * math.cos(2 * math.pi * i / n) * (1 + 0.05 * math.sin(7 * 2 * math.pi * i / n)), 4),
           round(75 * math.sin(2 * math.pi * i / n), 4)] for i in range(n)]
document = {"format": "kerf", "version": 1, "units": "mm", "name": "Long profile",
            "root": {"id": "p", "type": "extrude", "name": "Outline panel", "profile": points, "height": 18}}
out = sys.argv[1] if len(sys.argv) > 1 else "outline-panel-2000.kerf"
with open(out, "w") as f:
    json.dump(document, f)
