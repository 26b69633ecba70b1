"""Every link in the README and the docs/ pages resolves: a relative file
(or image) exists, and an #anchor names a heading of its page (GitHub's
slugs). The README is split into pages that link one another; a moved
section must not leave a dead link behind. And the README stays readable as
text: no line of it over 200 characters.

  docs_links_test.py SOURCE_DIR
"""
import glob
import os
import re
import sys

root = os.path.abspath(sys.argv[1])
pages = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))


def slug(heading):
    s = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return s.replace(" ", "-")


def anchors(path):
    text = open(path).read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # a comment in a code block is not a heading
    return {slug(m.group(1)) for m in re.finditer(r"(?m)^#{1,6} (.*)$", text)}


bad, checked = [], 0
for page in pages:
    text = re.sub(r"```.*?```", "", open(page).read(), flags=re.S)
    for m in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", text):
        target = m.group(1)
        if re.match(r"^(https?:|mailto:)", target):
            continue
        checked += 1
        path, _, anchor = target.partition("#")
        file = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        where = os.path.relpath(page, root)
        if not os.path.exists(file):
            bad.append("%s: %s: no such file" % (where, target))
        elif anchor and file.endswith(".md") and anchor not in anchors(file):
            bad.append("%s: %s: no heading '#%s' in %s" % (where, target, anchor, os.path.relpath(file, root)))
README_WIDTH = 200
long_lines = [(n, len(line)) for n, line in enumerate(open(pages[0]).read().split("\n"), 1) if len(line) > README_WIDTH]
for b in bad:
    print("dead link:", b)
for n, width in long_lines:
    print("README.md:%d: %d characters (at most %d)" % (n, width, README_WIDTH))
print("docs_links_test: %d links on %d pages, %d dead; %d README lines over %d characters"
      % (checked, len(pages), len(bad), len(long_lines), README_WIDTH))
sys.exit(1 if bad or long_lines else 0)
