#!/usr/bin/python3
"""Checks figures scripts/plot_tables.py wrote: DIR NAME... -> DIR/NAME.png is a PNG file and
DIR/NAME.svg parses as XML with an <svg> root. One line per failure on stderr, exit 1."""
import os
import sys
import xml.etree.ElementTree as ET

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def check(directory, name):
    errors = []
    png = os.path.join(directory, name + ".png")
    try:
        with open(png, "rb") as f:
            if f.read(len(PNG_MAGIC)) != PNG_MAGIC:
                errors.append(f"{png}: not a PNG file")
    except OSError as e:
        errors.append(f"{png}: {e}")
    svg = os.path.join(directory, name + ".svg")
    try:
        if not ET.parse(svg).getroot().tag.endswith("svg"):
            errors.append(f"{svg}: root element is not <svg>")
    except (OSError, ET.ParseError) as e:
        errors.append(f"{svg}: {e}")
    return errors


def main(argv):
    if len(argv) < 2:
        sys.stderr.write("usage: check_figures.py DIR NAME...\n")
        return 2
    errors = [e for name in argv[1:] for e in check(argv[0], name)]
    for e in errors:
        sys.stderr.write(e + "\n")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
