"""The folder map, found rather than listed: the layer folders at the repository root are
installed as subpackages of `taxel` (fem/ -> taxel.fem, ...), and every package below a
folder (a folder inside it, with Python or with data: setuptools.find_namespace_packages)
comes with it, so a new subpackage needs no entry anywhere. Everything else about the
package is in pyproject.toml; pip and the build backend run this file."""

from setuptools import find_namespace_packages, setup

FOLDERS = {"taxel": "taxel", "taxel.meshing": "meshing", "taxel.fem": "fem", "taxel.optimize": "optimize",
           "taxel.studies": "studies", "taxel.reports": "reports"}


def packages() -> list[str]:
    """Every package of the install: each folder's own and the ones found below it."""
    found = []
    for name, folder in FOLDERS.items():
        found += [name] + [f"{name}.{sub}" for sub in find_namespace_packages(folder, exclude=["*__pycache__*"])]
    return found


if __name__ == "__main__":
    setup(packages=packages(), package_dir=FOLDERS)
