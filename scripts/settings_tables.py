#!/usr/bin/env python3
"""Rewrites the settings tables of docs/techniques/*.md from the technique descriptors.

usage: scripts/settings_tables.py build/farfield

Each page holds its techniques' tables between `<!-- settings NAME -->` and
`<!-- /settings -->`; the text between is replaced by `farfield techniques --markdown`'s table
for NAME. tests/docs_test.cpp fails when a page and the descriptors disagree.
"""
import pathlib
import re
import subprocess
import sys

out = subprocess.run([sys.argv[1], "techniques", "--markdown"], check=True,
                     capture_output=True, text=True).stdout
tables = dict(re.findall(r"^### (\S+)\n\n(.*?)\n(?=### |\Z)", out, re.S | re.M))
docs = pathlib.Path(__file__).resolve().parent.parent / "docs" / "techniques"
for page in sorted(docs.glob("*.md")):
    text = page.read_text()
    new = re.sub(r"(<!-- settings (\S+) -->\n).*?(<!-- /settings -->)",
                 lambda m: m.group(1) + tables[m.group(2)] + m.group(3), text, flags=re.S)
    if new != text:
        page.write_text(new)
        print(f"updated {page.name}")
