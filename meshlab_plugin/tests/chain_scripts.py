#!/usr/bin/env python3
"""Chains shipped MeshLab filter scripts into one, as a user does who runs them one after the
other on one document, filling in the model file of every filter that has one.

  chain_scripts.py OUT.mlx MODEL_FILE SCRIPT.mlx [SCRIPT.mlx ...]

Every <filter> element of each script, in order, goes into OUT.mlx; a "model_file" parameter
gets MODEL_FILE as its value (kept as the script gives its type)."""
import sys
import xml.etree.ElementTree as ET


def main(out, model_file, scripts):
    chained = ET.Element("FilterScript")
    for path in scripts:
        for f in ET.parse(path).getroot().findall("filter"):
            for p in f.findall("Param"):
                if p.get("name") == "model_file":
                    p.set("value", model_file)
            chained.append(f)
    if not len(chained):
        sys.exit("chain_scripts.py: no <filter> in " + " ".join(scripts))
    with open(out, "w", encoding="utf-8") as o:
        o.write("<!DOCTYPE FilterScript>\n" + ET.tostring(chained, encoding="unicode") + "\n")


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
