"""`pip install ./clients/python` works offline, as clients/python/README.md says: into a fresh venv
that sees Debian's packages (python3-numpy, python3-setuptools, python3-wheel), without the network,
and the installed package is the one in the source tree.

    /usr/bin/python3 tests/python/pip_install_test.py -v
"""

import ast
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SOURCE = os.path.join(REPO, "clients", "python")

# Run by the venv's python from outside the source tree: where hrisim came from, and what it holds.
DESCRIBE_INSTALLED = """
import importlib, importlib.metadata, json, pkgutil
import hrisim
modules = sorted(m.name for m in pkgutil.iter_modules(hrisim.__path__))
for name in modules:
    importlib.import_module("hrisim." + name)  # every module imports with the declared dependencies
print(json.dumps({
    "file": hrisim.__file__,
    "version": hrisim.__version__,
    "distribution_version": importlib.metadata.version("hrisim"),
    "requires": importlib.metadata.requires("hrisim"),
    "modules": modules,
}))
"""


def stated_version():
    """``__version__`` of clients/python/hrisim/__init__.py, read without importing it."""
    with open(os.path.join(SOURCE, "hrisim", "__init__.py"), encoding="utf-8") as f:
        for node in ast.parse(f.read()).body:
            if isinstance(node, ast.Assign) and [t.id for t in node.targets] == ["__version__"]:
                return node.value.value
    raise AssertionError("clients/python/hrisim/__init__.py states no __version__")


class PipInstallTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="hrisim-pip-")
        self.addCleanup(shutil.rmtree, self.dir, True)

    def run_checked(self, *command, env=None):
        result = subprocess.run(command, cwd=self.dir, env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, timeout=240)
        self.assertEqual(result.returncode, 0, "%s failed:\n%s" % (" ".join(command), result.stdout))
        return result.stdout

    def test_pip_installs_the_client_offline_with_its_dependencies(self):
        # pip builds in the folder it is given (setuptools' build/ and hrisim.egg-info): a copy keeps
        # them out of the source tree.
        package = os.path.join(self.dir, "python")
        shutil.copytree(SOURCE, package, ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
        venv = os.path.join(self.dir, "venv")
        self.run_checked(sys.executable, "-m", "venv", "--system-site-packages", venv)
        python = os.path.join(venv, "bin", "python")
        env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "PIP_"))}
        env["PIP_CONFIG_FILE"] = os.devnull  # no index or options from the machine's pip.conf
        self.run_checked(python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir",
                         "./python", env=env)

        installed = json.loads(self.run_checked(python, "-c", DESCRIBE_INSTALLED, env=env).splitlines()[-1])
        venv_lib = os.path.realpath(os.path.join(venv, "lib"))
        self.assertTrue(os.path.realpath(installed["file"]).startswith(venv_lib), installed["file"])
        self.assertEqual(installed["version"], stated_version())
        self.assertEqual(installed["distribution_version"], stated_version())
        source_modules = sorted(name[:-3] for name in os.listdir(os.path.join(SOURCE, "hrisim"))
                                if name.endswith(".py") and name != "__init__.py")
        self.assertEqual(installed["modules"], source_modules)
        # as the metadata spells them, give or take spaces, brackets and quotes
        requires = {r.replace(" ", "").replace("(", "").replace(")", "").replace("'", '"')
                    for r in installed["requires"]}
        self.assertEqual(requires, {"numpy", 'gymnasium;extra=="gymnasium"'})


if __name__ == "__main__":
    unittest.main()
