#!/usr/bin/env python3
"""The include rules of docs/architecture.md hold on the tree, and the checker
catches each kind of break (shown on a small tree made here)."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECK = os.path.join(ROOT, 'scripts', 'checks', 'check_architecture.py')
RULES = os.path.join(ROOT, 'docs', 'architecture.md')


def run(root):
    p = subprocess.run([sys.executable, CHECK, '--root', root, '--rules', RULES], capture_output=True, text=True)
    return p.returncode, p.stdout


def tree(files):
    d = tempfile.mkdtemp()
    for path, text in files.items():
        os.makedirs(os.path.join(d, os.path.dirname(path)), exist_ok=True)
        with open(os.path.join(d, path), 'w') as f:
            f.write(text)
    return d


def expect_broken(files, needle):
    code, out = run(tree(files))
    assert code == 1 and needle in out, f'expected a broken rule naming {needle!r}, got exit {code}:\n{out}'


def main():
    code, out = run(ROOT)
    assert code == 0, 'the tree breaks the rules of docs/architecture.md:\n' + out
    ok = {'core/model/model.h': '#include <Eigen/Dense>\n#include <vector>\n',
          'core/dynamics/rnea.h': '#include "core/model/model.h"\n#include <cmath>\n',
          'server/app/server.cc': '#include "core/dynamics/rnea.h"\n#include "igms/robot_state_t.hpp"\n'
                                  '#include <lcm/lcm-cpp.hpp>\n'}
    code, out = run(tree(ok))
    assert code == 0, 'a tree that keeps the rules was reported broken:\n' + out
    expect_broken({**ok, 'core/dynamics/aba.h': '#include "server/app/server.h"\n'}, 'core/dynamics/aba.h:1')
    expect_broken({**ok, 'core/model/data.h': '#include "core/dynamics/rnea.h"\n'}, 'core/model may not include')
    expect_broken({**ok, 'core/simulation/x.h': '#include "igms/haptic_input_t.hpp"\n'}, 'lcmtypes/igms/')
    expect_broken({**ok, 'core/dynamics/x.cc': '#include <lcm/lcm-cpp.hpp>\n'}, '<lcm/lcm-cpp.hpp>')
    expect_broken({**ok, 'core/geometry/x.cc': '#include <fcl/fcl.h>\n'}, '<fcl/fcl.h>')
    expect_broken({**ok, 'haptic_client/servo/x.cc': '#include "server/loop/stepper.h"\n'}, 'haptic_client may not')
    expect_broken({**ok, 'server/x.cc': '#include "tools/replay/resimulate.h"\n'}, 'server may not include')
    expect_broken({**ok, 'tools/spy/x.cc': 'void f(lcm::LCM& lc) { lc.subscribe("A", &S::on, &s); }\n'},
                  'may not make the call lcm-subscribe')
    expect_broken({**ok, 'web/x.cc': 'auto* s = lcm_->subscribeFunction<F*>(".*", &F::on, this);\n'},
                  'may not make the call lcm-subscribe')
    # The geometry world's shapes are made in core/geometry alone; the others read them by reference.
    expect_broken({**ok, 'core/contact/x.cc': 'GeometryObject g;\n'}, 'may not make the call make-geometry-object')
    expect_broken({**ok, 'server/collision/x.cc': 'objects.push_back(GeometryObject{s, "link"});\n'},
                  'may not make the call make-geometry-object')
    code, out = run(tree({**ok, 'core/geometry/x.cc': 'GeometryObject g = objectOf(s, name);\n',
                          'core/interaction/y.cc': 'const GeometryObject& t = geometry.object(g);\n'}))
    assert code == 0, 'core/geometry making a GeometryObject, or a layer reading one, were reported broken:\n' + out
    code, out = run(tree({**ok, 'bus/x.h': 'lcm_.subscribeFunction<R*>(c, &R::arrived, this);\n',
                          'server/y.cc': 'auto in = bus::subscribe<haptic_input_t>(lc, v, "C", h);\n'}))
    assert code == 0, 'bus/ calling LCM, and a program calling bus::subscribe, were reported broken:\n' + out
    print('architecture_test: 15 passed, 0 failed')


if __name__ == '__main__':
    main()
