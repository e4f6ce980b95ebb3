"""The documentation: docs/model.md citations resolve, its function references exist, the site builds.

The site build needs the ``docs`` extras (``pip install -e '.[docs]'``); CI installs only ``test``,
so that test is skipped there, with the reason.
"""

import importlib
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

import lubelink.params as params

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "docs" / "model.md"
CITING = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "src").rglob("*.py")),
          *sorted((ROOT / "tests").rglob("*.py")), *sorted((ROOT / "examples").glob("*"))]


def _text(path):
    return path.read_text(encoding="utf-8")


def _sections():
    """Section numbers of docs/model.md: '1', '1.2', ... from its '## 1.' and '### 1.2' headings."""
    return set(re.findall(r"^#{2,4} (\d+(?:\.\d+)*)\.? ", _text(MODEL), flags=re.M))


def test_the_external_spec_is_not_cited():
    name = "MODEL" + ".md"  # spelled so that this file does not cite it
    citing = [str(p.relative_to(ROOT)) for p in CITING if p.is_file() and name in _text(p)]
    assert citing == []


def test_model_md_has_the_sections_the_code_cites():
    sections = _sections()
    assert {"1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11"} <= sections
    cited = []
    for path in CITING:
        if not path.is_file() or path == MODEL:
            continue
        text = _text(path)
        for match in re.finditer(r"model\.md\]?(?:\([^)]*\))?,? ?(?:§|section |sections )(\d+(?:\.\d+)*)"
                                 r"(?:(?:-|, §| and §?)(\d+(?:\.\d+)*))?", text):
            cited += [(path.name, number) for number in match.groups() if number]
        for match in re.finditer(r"model\.md\]?\([^)]*\)[^\n§]{0,20}§(\d+(?:\.\d+)*)", text):
            cited.append((path.name, match.group(1)))
    assert len(cited) > 30  # the pattern finds the citations (there are dozens)
    missing = sorted({(name, number) for name, number in cited if number not in sections})
    assert missing == []


# names in docs/model.md that look like module.function but are configuration keys
_CONFIG_SECTIONS = {"mechanism": params.Mechanism, "beam": params.Beam, "film": params.Film,
                    "collar": params.Collar, "contact": params.Contact, "model": params.ModelOptions,
                    "solver": params.Solver, "output": params.Output}


def _resolve(dotted):
    """The object ``lubelink.<dotted>``: attributes first (``film.pressure`` is the function the
    package exports), then submodules (``simulate.run``: ``lubelink.simulate`` is the function)."""
    import lubelink

    obj = lubelink
    try:
        for part in dotted.split("."):
            obj = getattr(obj, part) if hasattr(obj, part) else importlib.import_module(f"{obj.__name__}.{part}")
        return obj
    except (AttributeError, ImportError):
        pass
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module("lubelink." + ".".join(parts[:cut]))
        except ImportError:
            continue
        for part in parts[cut:]:
            obj = getattr(obj, part)
        return obj
    raise ImportError(dotted)


def test_functions_named_in_model_md_exist():
    text = _text(MODEL).replace("\\_", "_")
    names = set(re.findall(r"(?:`|\\texttt\{)([a-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)+)[`}]", text))
    checked = []
    for name in sorted(names):
        section, _, key = name.partition(".")
        fields = getattr(_CONFIG_SECTIONS.get(section), "__dataclass_fields__", {})
        if "." not in key and key in fields:
            continue  # a configuration key, e.g. film.cavitation
        if section not in {"beam", "film", "link", "contact", "compliant", "energy", "assembly", "simulate", "results",
                           "integrate", "params", "paper", "estimate", "_jit", "choice", "derived"}:
            continue
        assert callable(_resolve(name)) or isinstance(_resolve(name), type), name
        checked.append(name)
    assert len(checked) > 40, checked  # the doc names the implementing function of each equation


# --- the documentation site --------------------------------------------------------------------------
_TOOLS = ("mkdocs", "material", "mkdocstrings", "mkdocstrings_handlers.python")
_MISSING = [m for m in _TOOLS if importlib.util.find_spec(m.split(".")[0]) is None
            or (m == "mkdocstrings_handlers.python" and importlib.util.find_spec(m) is None)]
needs_docs_tools = pytest.mark.skipif(bool(_MISSING), reason=f"the docs tools are not installed ({', '.join(_MISSING)}); "
                                                              "pip install -e '.[docs]' to build the site")


@needs_docs_tools
def test_readme_links_become_site_links():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        from docs_hooks import readme_as_index
    finally:
        sys.path.pop(0)
    text = "[a](docs/paper.md) ![f](docs/figures/x.png) [b](docs/sweeps.md#validation) [c](https://x.org/y) [d](benchmarks/README.md)"
    assert readme_as_index(text) == ("[a](paper.md) ![f](figures/x.png) [b](sweeps.md#validation) "
                                     "[c](https://x.org/y) d (`benchmarks/README.md`)")


@pytest.mark.slow
@needs_docs_tools
def test_site_builds_with_api_reference_and_executed_gallery(tmp_path):
    site = tmp_path / "site"
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(site)], cwd=ROOT,
                          capture_output=True, text=True, timeout=3600,
                          env={**__import__("os").environ, "NO_MKDOCS_2_WARNING": "1", "LUBELINK_DOCS_EXECUTE": "1"})
    assert proc.returncode == 0, proc.stderr[-4000:]
    film_api = _text(site / "api" / "film" / "index.html")
    assert 'id="lubelink.film.force.modal_film_force"' in film_api
    assert "Gauss-Legendre" in film_api  # the docstring's text, not only the name
    gallery = _text(site / "gallery" / "film_models" / "index.html")
    assert "Output (run when this site was built" in gallery
    assert "film_breakdown" in gallery  # what the example printed: the reversed crank's wedge film breaks down
    model = _text(site / "model" / "index.html")
    assert 'id="43-first-integral"' in model  # the numbered sections the code cites are anchors
    index = _text(site / "index.html")
    assert 'href="model/"' in index  # README's link to docs/model.md works on the site


def test_every_page_is_in_the_navigation():
    """mkdocs only lists a page left out of ``nav`` at INFO level, which ``--strict`` lets through: every Markdown
    page under docs/ must be named in mkdocs.yml's navigation (figures/mode-convergence.md was not)."""
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8").split("\nnav:", 1)[1]
    named = set(re.findall(r"([\w./-]+\.md)\s*$", nav, flags=re.M))
    pages = {str(p.relative_to(ROOT / "docs")) for p in (ROOT / "docs").rglob("*.md")}
    assert pages and not pages - named, sorted(pages - named)
