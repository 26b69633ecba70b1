#!/usr/bin/env python3
"""Checks the include rules written in docs/architecture.md.

The rules are the lines of the fenced block that follows the heading
"## Rules" in that file, one per layer:

    core/dynamics: core/model core/kinematics

A file under the folder on the left may include (with #include "...") only
project headers under the folders on the right, its own folder, and the
headers named in "external" lines:

    external core/dynamics: <Eigen/ <cmath>

Angle-bracket includes are checked only for layers that have an "external"
line; those may include only what starts with one of the given prefixes or
is a C/C++ standard header. The most specific (longest) matching folder
decides. Files under no listed folder are not checked.

A "calls" line names a kind of call (one of CALLS below) and the only
layers whose files may make it:

    calls lcm-subscribe: bus
    calls make-geometry-object: core/geometry

    check_architecture.py [--root DIR] [--rules FILE]
Prints each broken rule as file:line: and exits 1 when any rule is broken.
"""
import argparse
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
# Headers generated at build time, by the folder they belong to.
GENERATED = (('channels.h', 'lcmtypes/channels.h'), ('igms/', 'lcmtypes/igms/'),
             ('igms_build_info.h', 'cmake/igms_build_info.h'))
SOURCE_ENDINGS = ('.h', '.hpp', '.cc', '.cpp')
# Calls a "calls" line can keep to some layers, by what they look like in the source.
CALLS = {
    # LCM's own subscribe (lc.subscribe(...), lcm_->subscribeFunction<T>(...)): a receive path that
    # could skip the message check or decode unguarded; bus::subscribe is the one way in.
    'lcm-subscribe': re.compile(r'(\.|->)\s*subscribe(Function)?\s*(<[^<>()]*>)?\s*\('),
    # A shape of the geometry world made (GeometryObject g; GeometryObject{...}; a vector of them
    # filled): one geometry model, built in one place, which the contact layer, the proxy and the
    # obstacle monitor index into. A reference (const GeometryObject& g) is reading, not making.
    'make-geometry-object': re.compile(
        r'\bGeometryObject\s*(\{|\(\s*\)|[A-Za-z_]\w*\s*[;{(=])|(push|emplace)_back\s*\(\s*GeometryObject\b'),
}


def read_rules(path):
    text = open(path, encoding='utf-8').read()
    m = re.search(r'^## Rules\s*$.*?^```[a-z]*\n(.*?)^```', text, re.S | re.M)
    if not m:
        raise SystemExit(f'{path}: no fenced block after "## Rules"')
    allowed, external, calls = {}, {}, {}
    for n, line in enumerate(m.group(1).splitlines(), 1):
        line = line.split('#', 1)[0].strip()
        if not line:
            continue
        head, _, rest = line.partition(':')
        if not _:
            raise SystemExit(f'{path}: rules line {n}: expected "layer: allowed ..."')
        words = head.split()
        if len(words) == 2 and words[0] == 'calls':
            if words[1] not in CALLS:
                raise SystemExit(f'{path}: rules line {n}: unknown call "{words[1]}" (known: {" ".join(CALLS)})')
            calls[words[1]] = [w.rstrip('/') for w in rest.split()]
        elif len(words) == 2 and words[0] == 'external':
            external[words[1].rstrip('/')] = rest.split()
        elif len(words) == 1:
            allowed[words[0].rstrip('/')] = [w.rstrip('/') for w in rest.split()]
        else:
            raise SystemExit(f'{path}: rules line {n}: cannot read "{line}"')
    return allowed, external, calls


def layer_of(rel, layers):
    best = None
    for layer in layers:
        if rel == layer or rel.startswith(layer + '/'):
            if best is None or len(layer) > len(best):
                best = layer
    return best


def is_standard(header):
    # <vector>, <cstdio>, <atomic>: no dot, no slash; C headers such as <time.h>, <sys/stat.h>.
    return ('.' not in header and '/' not in header) or re.fullmatch(
        r'(sys/)?[a-z_]+\.h', header) is not None


def check(root, rules_path):
    allowed, external, calls = read_rules(rules_path)
    layers = set(allowed) | set(external)
    problems = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames if not d.startswith('.') and d not in ('build', 'out')]
        for name in filenames:
            if not name.endswith(SOURCE_ENDINGS):
                continue
            path = os.path.join(dirpath, name)
            rel = os.path.relpath(path, root)
            layer = layer_of(rel, layers)
            if layer is None:
                continue
            ok_dirs = [layer] + allowed.get(layer, [])
            with open(path, encoding='utf-8', errors='replace') as f:
                for n, line in enumerate(f, 1):
                    code = line.split('//', 1)[0]
                    for call, layers_allowed in calls.items():
                        if CALLS[call].search(code) and layer_of(rel, layers_allowed) is None:
                            problems.append(f'{rel}:{n}: {layer} may not make the call {call} '
                                            f'(only: {" ".join(layers_allowed)})')
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    kind, header = m.groups()
                    if kind == '"':
                        for prefix, where in GENERATED:
                            if header == prefix or (prefix.endswith('/') and header.startswith(prefix)):
                                header = where + header[len(prefix):] if prefix.endswith('/') else where
                                break
                        else:
                            if '/' not in header:  # beside the including file
                                header = os.path.relpath(os.path.join(os.path.dirname(rel), header))
                        if layer_of(header, ok_dirs) is None:
                            problems.append(f'{rel}:{n}: {layer} may not include "{header}" '
                                            f'(allowed: {" ".join(ok_dirs)})')
                    elif layer in external:
                        prefixes = external[layer]
                        if not is_standard(header) and not any(header.startswith(p.strip('<')) for p in prefixes):
                            problems.append(f'{rel}:{n}: {layer} may not include <{header}> '
                                            f'(allowed: the standard library and {" ".join(prefixes) or "nothing else"})')
    return problems


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description='Check the include rules of docs/architecture.md.')
    p.add_argument('--root', default=os.path.dirname(os.path.dirname(here)))
    p.add_argument('--rules', default=None)
    a = p.parse_args()
    rules = a.rules or os.path.join(a.root, 'docs', 'architecture.md')
    problems = check(a.root, rules)
    for line in problems:
        print(line)
    print(f'architecture: {len(problems)} broken rule(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
