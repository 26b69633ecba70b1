"""The command lines the README and the docs/ pages show stay true: in every
fenced block, each igms program named exists in the build, each subcommand
is one it has, and each --option written after it (synopses' [--option]
included) is one its --help lists; each scripts/ file named exists. The
walkthrough (walkthrough_test), the environment commands (docs/environment.md's
igms-scenario line, environment_session_test) and the launchers' own tests run
theirs; this catches the rest going stale when an option is renamed.

  docs_commands_test.py SOURCE_DIR BUILD_DIR
"""
import glob
import os
import re
import subprocess
import sys

root, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
# docs/architecture.md's blocks are diagrams, not commands.
pages = [os.path.join(root, "README.md")] + sorted(p for p in glob.glob(os.path.join(root, "docs", "*.md"))
                                                   if not p.endswith("architecture.md"))
help_cache = {}


def program_path(name):
    for folder in ("server", "haptic_client", "tools", "bench"):
        path = os.path.join(build, folder, name)
        if os.path.exists(path):
            return path
    path = os.path.join(root, ".venv", "bin", name)  # igms-sweep: the Python module's (scripts/setup/setup.sh)
    return path if os.path.exists(path) else None


def help_text(path, sub=None):
    key = (path, sub)
    if key not in help_cache:
        args = [path] + ([sub] if sub else []) + ["--help"]
        r = subprocess.run(args, capture_output=True, text=True, timeout=20)
        help_cache[key] = (r.returncode, r.stdout + r.stderr)
    return help_cache[key]


bad, checked = [], 0
for page in pages:
    where = os.path.relpath(page, root)
    for block in re.findall(r"```(?:bash|sh|)\n(.*?)```", open(page).read(), re.S):
        text = re.sub(r"\\\n", " ", block)  # continued lines are one command
        for line in text.split("\n"):
            line = re.sub(r"\s#\s.*$", "", line)  # a comment
            for segment in re.split(r"\|\||&&|\||;|&(?!\S)", line):
                tokens = segment.split()
                for k, token in enumerate(tokens):
                    if re.match(r"^(bash )?scripts/[\w./-]+\.(sh|py)$", token) and not token.endswith("..."):
                        checked += 1
                        if not os.path.exists(os.path.join(root, token)):
                            bad.append("%s: %s: no such script" % (where, token))
                    m = re.match(r"^(?:[\w./-]*/)?(igms-[a-z-]+)$", token)
                    if not m or m.group(1) in ("igms-bench",):  # igms-bench takes Google Benchmark's flags
                        continue
                    # A command: the program first (after VAR=value, or a launcher's `run`), not a word in prose or a tree.
                    before = [t for t in tokens[:k] if not re.match(r"^[A-Z_]+=", t)]
                    if before and before[-1] not in ("run", "exec", "sudo", "timeout") and \
                            not before[0].startswith("scripts/"):
                        continue
                    name = m.group(1)
                    path = program_path(name)
                    checked += 1
                    if not path:
                        bad.append("%s: %s: no such program in the build" % (where, name))
                        continue
                    rest = tokens[k + 1:]
                    sub = None
                    if rest and re.match(r"^[a-z]+$", rest[0]):
                        code, _ = help_text(path, rest[0])
                        sub = rest[0] if code == 0 else None
                    code, text_help = help_text(path, sub)
                    if code != 0:
                        bad.append("%s: %s %s --help failed" % (where, name, sub or ""))
                        continue
                    for t in rest:
                        for option in re.findall(r"(?:^|\[|\|)(--[a-z][a-z0-9-]*)", t):
                            checked += 1
                            if not re.search(r"(?<![\w-])" + re.escape(option) + r"(?![\w-])", text_help):
                                bad.append("%s: %s%s: %s is not an option it lists" % (
                                    where, name, " " + sub if sub else "", option))
for b in bad:
    print("stale:", b)
print("docs_commands_test: %d programs, scripts and options checked on %d pages, %d stale" % (
    checked, len(pages), len(bad)))
sys.exit(1 if bad else 0)
