"""What a computation runs, as one fingerprint: the code part of every result cache key.

A cached result may be served only where the code would compute it again. So the fingerprint
(:func:`code_version`) holds

* every repository module the computation imports, found from the import graph
  (:func:`imported_modules`): the closure of the module that holds
  :func:`comparison.runner.runner.compute` (:data:`COMPUTATION`) over every ``import`` statement,
  wherever it stands (at the top, inside a function, under ``TYPE_CHECKING``), with the package
  ``__init__`` modules an import runs; a module that imports by name at run time
  (``importlib.import_module``, as the back-end registry does) brings in every module of its folder.
  The graph is followed, not listed by hand, so a module a computation comes to import joins the key
  by itself; it errs on the side of too many modules (an edit of one the computation never calls
  recomputes results it did not have to), never too few;
* what each of them *does* (:func:`behaviour`: the syntax tree without docstrings): a docstring,
  comment or layout edit keeps every cached result, any other edit is a new fingerprint;
* the versions of the third-party packages those modules import (:func:`dependency_versions`:
  numpy, scipy, highspy, clarabel, cvxopt, numba...), read from the graph too, and Python's minor
  version: results computed under another solver are computed again.

Parsing every module costs a few hundred milliseconds, so each file's behaviour hash and imports are
memoised on its path, size, modification and change times and inode (:class:`ModuleMemo`, one
``modules.memo`` in the cache folder): a warm key stats the files and parses none.
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import re
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

from comparison.utilities.inputs import read_input_file
from comparison.utilities.outputs import write_atomic

#: The module that holds :func:`~comparison.runner.runner.compute`: where the import graph starts.
COMPUTATION = "comparison.runner.runner"
#: The repository's import packages (the only modules the graph follows; every other import is a
#: third-party package, whose version counts, or the standard library).
REPOSITORY_PACKAGES = ("comparison", "macro", "micro")
#: The file in a cache folder that memoises each module's hash (:class:`ModuleMemo`).
MEMO_FILE = "modules.memo"
#: The largest memo read (bytes): a few hundred bytes per module, for about 150 modules.
MAX_MEMO_BYTES = 1 << 20

ROOT = Path(__file__).resolve().parents[2]
#: The files read by this process, as :class:`ModuleMemo` keeps them (shared by every memo).
_READ: dict[str, list[Any]] = {}


def source(path: Path) -> bytes:
    """The source of a module the fingerprint hashes (a seam for its tests)."""
    return path.read_bytes()


def behaviour(text: bytes) -> bytes:
    """What a module's source does: the dump of its syntax tree with every docstring (a string standing
    alone as a statement) removed; comments and layout are not in the tree. A source that does not parse
    counts by its bytes (it cannot run either)."""
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return b"unparsed:" + text
    return _without_docstrings(tree)


def _without_docstrings(tree: ast.Module) -> bytes:
    """The dump of ``tree`` with its docstrings removed (the tree is changed)."""
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list):
            node.body = [s for s in body  # type: ignore[attr-defined]
                         if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant)
                                 and isinstance(s.value.value, str))]
    return ast.dump(tree, annotate_fields=False).encode()


@dataclass(frozen=True)
class ModuleFacts:
    """What the fingerprint needs of one module file.

    Attributes:
        sha: the hash of its :func:`behaviour`.
        imports: the absolute names it imports (for ``from a import b``: ``a`` and ``a.b``, since ``b``
            may be a module).
        by_name: it imports modules by name at run time (``importlib.import_module``).
    """

    sha: str
    imports: tuple[str, ...]
    by_name: bool


def read_facts(path: Path, package: str) -> ModuleFacts:
    """The :class:`ModuleFacts` of the file ``path``, a module of ``package`` (its own name for an
    ``__init__``), read and parsed now."""
    text = source(path)
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError):
        return ModuleFacts(hashlib.sha256(b"unparsed:" + text).hexdigest(), (), False)
    names: set[str] = set()
    by_name = False
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - (node.level - 1)] + ([node.module] if node.module else []))
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names if alias.name != "*")
        elif isinstance(node, ast.Call):
            func = node.func
            called = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else ""
            by_name = by_name or called == "import_module"
    sha = hashlib.sha256(_without_docstrings(tree)).hexdigest()
    return ModuleFacts(sha, tuple(sorted(n for n in names if n)), by_name)


class ModuleMemo:
    """Each module file's :class:`ModuleFacts`, memoised on its path, size, modification and change times
    and inode, in memory and (when given a folder) in its ``modules.memo``.

    A file whose stat differs from the memoised one is read again. A memo file that cannot be read
    (missing, damaged, of another form, a symbolic link) counts as empty; one that cannot be written is
    left as it is: the memo only saves time, it never decides a key on its own.
    """

    def __init__(self, folder: Path | None) -> None:
        self.path = None if folder is None else Path(folder) / MEMO_FILE
        self.entries: dict[str, list[Any]] = self._load()
        self.changed = False

    def _load(self) -> dict[str, list[Any]]:
        if self.path is None:
            return {}
        try:
            stored = json.loads(read_input_file(self.path, MAX_MEMO_BYTES, follow_symlinks=False))
        except (OSError, ValueError):
            return {}
        if not isinstance(stored, dict):
            return {}
        return {k: v for k, v in stored.items() if isinstance(v, list) and len(v) == 4}

    def facts(self, path: Path, package: str) -> ModuleFacts:
        """The facts of ``path`` (a module of ``package``), from the memo when its stat is unchanged."""
        st = path.stat()
        stamp = [st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_ino]
        key = str(path)
        for memo in (self.entries, _READ):
            found = memo.get(key)
            if found is not None and found[0] == stamp:
                try:
                    facts = ModuleFacts(str(found[1]), tuple(str(n) for n in found[2]), bool(found[3]))
                    break
                except TypeError:
                    continue
        else:
            facts = read_facts(path, package)
        entry = [stamp, facts.sha, list(facts.imports), facts.by_name]
        if self.entries.get(key) != entry:
            self.entries[key] = _READ[key] = entry
            self.changed = True
        return facts

    def save(self) -> None:
        """Write the memo back when a file was read anew (whole or not at all; silently not at all)."""
        if self.path is None or not self.changed:
            return
        kept = {key: entry for key, entry in self.entries.items() if Path(key).is_file()}
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            write_atomic(self.path, json.dumps(kept, separators=(",", ":")).encode(), follow_symlinks=False)
        except OSError:
            pass
        self.changed = False


def module_file(name: str, root: Path = ROOT) -> Path | None:
    """The file of the repository module ``name`` under ``root`` (``None``: not a repository module)."""
    if name.split(".")[0] not in REPOSITORY_PACKAGES:
        return None
    base = os.path.join(root, *name.split("."))
    for candidate in (os.path.join(base, "__init__.py"), base + ".py"):
        if os.path.isfile(candidate):
            return Path(candidate)
    return None


@dataclass(frozen=True)
class ImportGraph:
    """The closure of one module over the import graph.

    Attributes:
        modules: each repository module imported, by name, with its file and behaviour hash.
        third_party: the top-level names of the other packages those modules import (not the standard
            library's).
    """

    modules: Mapping[str, tuple[Path, str]]
    third_party: tuple[str, ...]


def imported_modules(entry: str = COMPUTATION, memo: ModuleMemo | None = None, root: Path = ROOT) -> ImportGraph:
    """Every repository module that importing ``entry`` and running its functions may import (module
    docstring), with the third-party packages they import."""
    memo = memo if memo is not None else ModuleMemo(None)
    found: dict[str, tuple[Path, str]] = {}
    others: set[str] = set()
    todo = [entry]
    named: set[str] = set()
    while todo:
        name = todo.pop()
        if name in named:
            continue
        named.add(name)
        parts = name.split(".")
        if parts[0] not in REPOSITORY_PACKAGES:
            if parts[0] not in sys.stdlib_module_names and parts[0] != "__future__":
                others.add(parts[0])
            continue
        for i in range(1, len(parts) + 1):  # the packages an import runs, then the module itself
            module = ".".join(parts[:i])
            path = None if module in found else module_file(module, root)
            if path is None:
                continue
            package = module if path.name == "__init__.py" else module.rpartition(".")[0]
            facts = memo.facts(path, package)
            found[module] = (path, facts.sha)
            todo += facts.imports
            if facts.by_name:
                todo += _folder_modules(path.parent, package)
    return ImportGraph(dict(sorted(found.items())), tuple(sorted(others)))


def _folder_modules(folder: Path, package: str) -> Iterable[str]:
    """The modules of the folder ``folder`` (the package ``package``), at any depth."""
    for path in sorted(folder.rglob("*.py")):
        rel = path.relative_to(folder).with_suffix("").parts
        yield ".".join((package, *(rel[:-1] if rel[-1] == "__init__" else rel)))


def _normalized(name: str) -> str:
    """A distribution's name as its ``.dist-info`` folder spells it, lower case (PEP 503, 427)."""
    return re.sub(r"[-_.]+", "_", name).lower()


@cache
def _dist_info_versions() -> dict[str, str]:
    """The version of each distribution on ``sys.path``, from its ``NAME-VERSION.dist-info`` folder (the
    first on the path, as an import finds it): a directory listing per path entry, where reading each
    distribution's metadata would be most of a warm key's cost (docs/speed.md)."""
    found: dict[str, str] = {}
    for entry in sys.path:
        try:
            names = os.listdir(entry or ".")
        except OSError:
            continue
        for folder in names:
            if folder.endswith(".dist-info"):
                dist, _, version = folder[: -len(".dist-info")].partition("-")
                found.setdefault(_normalized(dist), version)
    return found


def distribution_version(name: str) -> str:
    """The installed version of the package imported as ``name`` (``"not installed"`` when none is)."""
    version = _dist_info_versions().get(_normalized(name))
    if version:
        return version
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        pass
    for dist in metadata.packages_distributions().get(name, ()):
        try:
            return metadata.version(dist)
        except metadata.PackageNotFoundError:
            continue
    return "not installed"


def dependency_versions(names: Iterable[str]) -> dict[str, str]:
    """The versions of the third-party packages ``names`` (a seam for the tests)."""
    return {name: distribution_version(name) for name in names}


def python_minor() -> str:
    """Python's ``major.minor`` (a seam for the tests)."""
    return f"{sys.version_info.major}.{sys.version_info.minor}"


@dataclass(frozen=True)
class Fingerprint:
    """What a computation runs (module docstring).

    Attributes:
        modules: each imported repository module's path (relative to the repository) and behaviour hash.
        versions: the version of each third-party package they import.
        python: Python's ``major.minor``.
    """

    modules: Mapping[str, str]
    versions: Mapping[str, str]
    python: str

    @property
    def digest(self) -> str:
        """The fingerprint as 16 hexadecimal digits (the cache key's ``code``)."""
        text = json.dumps({"modules": self.modules, "versions": self.versions, "python": self.python},
                          sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@cache
def fingerprint(memo_folder: Path | None = None) -> Fingerprint:
    """The :class:`Fingerprint` of the computation, once per process and memo folder (the code a process
    runs is the code it imported at its start). ``memo_folder``: where ``modules.memo`` lives (a result
    cache folder; ``None``: memoised in memory only)."""
    memo = ModuleMemo(memo_folder)
    graph = imported_modules(COMPUTATION, memo, ROOT)
    memo.save()
    modules = {path.relative_to(ROOT).as_posix(): sha for path, sha in graph.modules.values()}
    return Fingerprint(modules, dependency_versions(graph.third_party), python_minor())


def code_version(memo_folder: Path | None = None) -> str:
    """The fingerprint of what a computation runs, as 16 hexadecimal digits (:class:`Fingerprint`)."""
    return fingerprint(memo_folder).digest


def versions_used() -> dict[str, str]:
    """Python's version, this package's and the versions of the packages a computation imports: what a
    cached result was computed under, since they are part of its key (the report's, the sweeps' and the
    plugin references' record of versions)."""
    return {"python": sys.version.split()[0], "xcheck-masonry": distribution_version("xcheck-masonry"),
            **fingerprint().versions}
