"""Every command block of the README and the docs/ pages is run by a test.

  - A ```bash block with no mark is run here, as written, with bash -e, from a
    scratch folder that holds the repository's files (links) and the build,
    so what it writes (out/, /tmp aside) goes nowhere; it must exit 0 within
    its time (180 s). A block that uses the bus starts its own private network
    namespace (scripts/netns_run.sh), as every udpm:// user here must.
  - `<!-- run by: NAME[, NAME] -->` on the line before: each NAME is a ctest
    test (or a repository file, such as .ci/run) that runs the block; the test
    must exist, and its files (or the files its CMake lines name) must name
    every program and script the block starts.
  - `<!-- synopsis -->`: a command's syntax (placeholders, [--options]); not
    run, and docs_commands_test checks its programs, scripts and options.
  - A page's ```python blocks with no mark are one script, in the page's order
    (a walkthrough: later blocks use what earlier ones made), run here with
    the project's .venv and the build's igms module (PYTHONPATH=build/python)
    from the same kind of scratch folder, inside a private network namespace
    (a sweep's local Ray); it must exit 0 within PYTHON_SECONDS.
  - Any other block says what it is (```text for output, trees and diagrams;
    ```yaml, ```cmake, ...): a block with no language fails here.

  docs_blocks_test.py SOURCE_DIR BUILD_DIR
"""
import glob
import os
import re
import subprocess
import sys
import tempfile
import time

root, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
pages = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))
RUN_SECONDS = 180
PYTHON_SECONDS = 300


def blocks(page):
    """(line, language, mark, body) of each fenced block; mark: the HTML comment on the line before."""
    text = open(page).read()
    for m in re.finditer(r"^( *)```([\w+-]*)\n(.*?)^ *```[ \t]*$", text, re.S | re.M):
        line = text.count("\n", 0, m.start()) + 1
        before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1].strip()
        mark = re.fullmatch(r"<!--\s*(.*?)\s*-->", before)
        body = "\n".join(l[len(m.group(1)):] if l.startswith(m.group(1)) else l
                         for l in m.group(3).split("\n"))
        yield line, m.group(2), mark.group(1) if mark else None, body


def key_tokens(body):
    """What a runner must name: each program and script the block starts (basenames), and a bare
    command's first word with its first --option (cmake --install)."""
    out = set()
    text = re.sub(r"\\\n", " ", body)
    for line in text.split("\n"):
        line = re.sub(r"(^|\s)#.*$", "", line).strip()
        if not line:
            continue
        for token in re.findall(r"[\w./$()-]+", line):
            m = re.match(r"^(?:[\w./-]*/)?(igms-[a-z-]+)$", token)
            if m:
                out.add(m.group(1))
            elif re.match(r"^(?:scripts|examples)/[\w./-]+$", token):
                out.add(os.path.basename(token.rstrip("/")))
        words = line.split()
        if words and words[0] in ("cmake",) and len(words) > 1 and words[1].startswith("--"):
            out.add(words[0] + " " + words[1])
    return out


def ctest_names():
    """The build's tests, from its CTestTestfile.cmake files (running ctest -N here would overwrite the
    running ctest's Testing/Temporary/LastTest.log)."""
    names = set()
    for f in glob.glob(os.path.join(build, "**", "CTestTestfile.cmake"), recursive=True):
        names |= set(re.findall(r"^add_test\(\[=\[(.+?)\]=\]", open(f).read(), re.M))
    return names


def runner_text(name):
    """The text of a runner: a repository file, or a ctest test's CMake lines and the files they name."""
    path = os.path.join(root, name)
    if os.path.isfile(path):
        return open(path).read()
    text = ""
    for cmake in glob.glob(os.path.join(root, "tests", "**", "CMakeLists.txt"), recursive=True):
        src = open(cmake).read()
        for m in re.finditer(r"(?:add_test\(NAME|igms_add_test\()\s*" + re.escape(name) + r"\b", src):
            end = src.find("set_tests_properties", m.end())
            stanza = src[m.start():end if end > 0 else len(src)]
            text += stanza
            for f in re.findall(r"\$\{PROJECT_SOURCE_DIR\}/([\w./-]+)", stanza):
                if os.path.isfile(os.path.join(root, f)):
                    text += open(os.path.join(root, f)).read()
            for f in re.findall(r"SOURCES\s+([\w./-]+)", stanza):
                p = os.path.join(root, "tests", f)
                if os.path.isfile(p):
                    text += open(p).read()
    # The test support modules a runner imports run its commands too.
    for module in set(re.findall(r"^\s*(?:import|from)\s+(\w+)", text, re.M)):
        p = os.path.join(root, "tests", "support", module + ".py")
        if os.path.isfile(p):
            text += open(p).read()
    return text


def sandbox():
    """A scratch folder with the repository's entries linked in, and build/ the build."""
    d = tempfile.mkdtemp(prefix="igms-docs-blocks-")
    for entry in os.listdir(root):
        if entry in (".git", "build", "out"):
            continue
        os.symlink(os.path.join(root, entry), os.path.join(d, entry))
    os.symlink(build, os.path.join(d, "build"))
    return d


def run_python(where, script, first_line):
    """A page's unmarked python blocks, as one script."""
    work = sandbox()
    t0 = time.time()
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"), MPLBACKEND="Agg")
    try:
        with open(os.path.join(work, "docs_blocks.py"), "w") as f:
            f.write(script)
        r = subprocess.run([os.path.join(root, "scripts", "netns_run.sh"), os.path.join(root, ".venv", "bin", "python"),
                            "docs_blocks.py"], cwd=work, capture_output=True, text=True, timeout=PYTHON_SECONDS,
                           env=env)
        code, output = r.returncode, r.stdout + r.stderr
    except subprocess.TimeoutExpired as e:
        code, output = "timeout", (e.stdout or b"").decode(errors="replace")
    finally:
        subprocess.run(["rm", "-rf", work])
    print("ran %s:%d and the page's other python blocks (%.1f s): exit %s" % (where, first_line, time.time() - t0, code))
    return None if code == 0 else "%s: its python blocks exit %s:\n%s" % (
        where, code, "\n".join(output.strip().split("\n")[-15:]))


tests = ctest_names()
bad, ran, delegated, synopses, described = [], 0, 0, 0, 0
for page in pages:
    where = os.path.relpath(page, root)
    python = [(line, body) for line, lang, mark, body in blocks(page) if lang == "python" and not mark]
    if python:
        script = "".join("# %s:%d\n%s\n" % (where, line, body) for line, body in python)
        failure = run_python(where, script, python[0][0])
        ran += len(python)
        if failure:
            bad.append(failure)
    for line, lang, mark, body in blocks(page):
        if lang == "python" and not mark:
            continue
        at = "%s:%d" % (where, line)
        if not lang:
            bad.append("%s: a block with no language (```bash, ```text, ```yaml ...)" % at)
            continue
        if lang != "bash":
            described += 1
            continue
        if mark == "synopsis":
            synopses += 1
            continue
        if mark and mark.startswith("run by:"):
            names = [n.strip() for n in mark[len("run by:"):].split(",") if n.strip()]
            text = ""
            for n in names:
                if n not in tests and not os.path.isfile(os.path.join(root, n)):
                    bad.append("%s: run by %s: no such test or file" % (at, n))
                text += runner_text(n)
            # A runner that reads the page's blocks itself (walkthrough_test) runs each as written.
            reads_page = os.path.relpath(page, root) in text and "```bash" in text
            missing = [] if reads_page else sorted(t for t in key_tokens(body) if t not in text)
            if missing:
                bad.append("%s: run by %s, which never names %s" % (at, ", ".join(names), ", ".join(missing)))
            delegated += 1
            continue
        if mark:
            bad.append("%s: unknown mark <!-- %s --> (run by: NAME, or synopsis)" % (at, mark))
            continue
        if "udpm://" in body or re.search(r"igms-(server|haptic|logger|viewer|relay|spy|command)\b", body):
            if "netns_run.sh" not in body:
                bad.append("%s: uses the bus outside a private namespace (scripts/netns_run.sh)" % at)
                continue
        work = sandbox()
        t0 = time.time()
        try:
            r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", body], cwd=work, capture_output=True,
                               text=True, timeout=RUN_SECONDS)
            code, output = r.returncode, r.stdout + r.stderr
        except subprocess.TimeoutExpired as e:
            code, output = "timeout", (e.stdout or b"").decode(errors="replace")
        finally:
            subprocess.run(["rm", "-rf", work])
        ran += 1
        print("ran %s (%.1f s): exit %s" % (at, time.time() - t0, code))
        if code != 0:
            bad.append("%s: exit %s:\n%s" % (at, code, "\n".join(output.strip().split("\n")[-15:])))
for b in bad:
    print("FAIL", b)
print("docs_blocks_test: %d blocks run here, %d run by named tests, %d synopses, %d other blocks; %d failed"
      % (ran, delegated, synopses, described, len(bad)))
sys.exit(1 if bad else 0)
