"""The documentation: docs/model.md citations resolve, its function references exist, the site builds.

The site build needs the docs tools, which the ``test`` extras include (``docs``); where they are
missing the site's tests are skipped, with the reason. The site is built without running the
gallery's examples (``tests/test_examples.py`` runs them); ``LUBELINK_DOCS_EXECUTE=1 python -m pytest
tests/test_docs.py`` builds it with them run, as ``mkdocs build`` does.
"""

import html.parser
import importlib
import importlib.util
import os
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
                           "integrate", "params", "paper", "estimate", "_jit", "choice", "derived", "coupling"}:
            continue
        assert callable(_resolve(name)) or isinstance(_resolve(name), type), name
        checked.append(name)
    assert len(checked) > 40, checked  # the doc names the implementing function of each equation


# --- the documentation site --------------------------------------------------------------------------
_TOOLS = ("mkdocs", "material", "mkdocstrings", "mkdocstrings_handlers.python", "math_core")
_MISSING = [m for m in _TOOLS if importlib.util.find_spec(m.split(".")[0]) is None
            or (m == "mkdocstrings_handlers.python" and importlib.util.find_spec(m) is None)]
needs_docs_tools = pytest.mark.skipif(bool(_MISSING), reason=f"the docs tools are not installed ({', '.join(_MISSING)}); "
                                                              "pip install -e '.[docs]' to build the site")
# the tests of the built site share one build, on one xdist worker
same_build = pytest.mark.xdist_group("docs-site")


def test_ci_has_the_docs_tools():
    """CI installs the ``test`` extras, which include the docs tools: there the site's tests must run, not skip."""
    if os.environ.get("CI"):
        assert _MISSING == []


def _hooks():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import docs_hooks
    finally:
        sys.path.pop(0)
    return docs_hooks


def _mkdocs_build(cwd, site, execute="0"):
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "LUBELINK_DOCS_EXECUTE": execute}
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(site)], cwd=cwd,
                          capture_output=True, text=True, timeout=3600, env=env)


@needs_docs_tools
def test_readme_links_become_site_links():
    text = "[a](docs/paper.md) ![f](docs/figures/x.png) [b](docs/sweeps.md#validation) [c](https://x.org/y) [d](benchmarks/README.md)"
    assert _hooks().readme_as_index(text) == ("[a](paper.md) ![f](figures/x.png) [b](sweeps.md#validation) "
                                              "[c](https://x.org/y) d (`benchmarks/README.md`)")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site, built as CI builds it: strict, the examples not run unless ``LUBELINK_DOCS_EXECUTE=1``."""
    site = tmp_path_factory.mktemp("docs") / "site"
    proc = _mkdocs_build(ROOT, site, execute=os.environ.get("LUBELINK_DOCS_EXECUTE", "0"))
    assert proc.returncode == 0, proc.stderr[-4000:]
    return site


@needs_docs_tools
@same_build
def test_site_builds_with_api_reference_and_gallery(site):
    film_api = _text(site / "api" / "film" / "index.html")
    assert 'id="lubelink.film.force.modal_film_force"' in film_api
    assert "Gauss-Legendre" in film_api  # the docstring's text, not only the name
    gallery = _text(site / "gallery" / "film_models" / "index.html")
    if os.environ.get("LUBELINK_DOCS_EXECUTE", "0") not in ("0", "false", "no"):
        assert "Output (run when this site was built" in gallery
        assert "film_breakdown" in gallery  # what the example printed: the reversed crank's wedge film breaks down
    else:
        assert "Not run when this site was built" in gallery
    model = _text(site / "model" / "index.html")
    assert 'id="43-first-integral"' in model  # the numbered sections the code cites are anchors
    index = _text(site / "index.html")
    assert 'href="model/"' in index  # README's link to docs/model.md works on the site
    assert 'href="gallery/film_models/"' in index  # the gallery's pages are in the navigation


class _Page(html.parser.HTMLParser):
    """What a page loads (``src``, ``href`` of everything but links, ``data``) and its text outside code and math."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.loads, self.text, self.formulas, self._inside = [], [], 0, []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.loads += [attrs[key] for key in ("src", "data", "srcset") if attrs.get(key)]
        if tag != "a" and attrs.get("href"):
            self.loads.append(attrs["href"])
        self.formulas += tag == "math"
        if tag in ("pre", "code", "math", "script", "style"):
            self._inside.append(tag)

    def handle_endtag(self, tag):
        if tag in self._inside:
            del self._inside[len(self._inside) - 1 - self._inside[::-1].index(tag):]

    def handle_data(self, data):
        if not self._inside:
            self.text.append(data)


def _pages(site):
    for path in sorted(site.rglob("*.html")):
        page = _Page()
        page.feed(_text(path))
        yield path.relative_to(site), page


_EXTERNAL = re.compile(r"^(?:[a-z][a-z0-9+.-]*:)?//", re.I)


@needs_docs_tools
@same_build
def test_site_loads_nothing_from_elsewhere(site):
    """Read offline, every page shows: no script, style sheet, font or image is fetched from another host."""
    external = [(str(path), url) for path, page in _pages(site) for url in page.loads if _EXTERNAL.match(url)]
    for css in site.rglob("*.css"):
        external += [(str(css.relative_to(site)), url)
                     for url in re.findall(r"""(?:url\(|@import\s+)["']?((?:[a-z]+:)?//[^"')\s]+)""", _text(css))]
    assert external == []


@needs_docs_tools
@same_build
def test_formulas_are_mathml_written_at_build_time(site):
    pages = dict(_pages(site))
    assert pages[Path("model/index.html")].formulas > 400  # docs/model.md has about 500
    assert not list(site.rglob("*mathjax*"))
    for path, page in pages.items():
        text = "".join(page.text)
        assert "\\(" not in text and "\\[" not in text, path  # no formula left for a script to typeset
        assert "$" not in text, (path, re.findall(r".{0,40}\$.{0,40}", text))  # nor one Markdown did not see


@needs_docs_tools
def test_a_formula_that_does_not_convert_fails_the_build(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "index.md").write_text("# Formulas\n\nGood $u_2''$, bad $\\frac{a}{b$.\n", encoding="utf-8")
    (tmp_path / "hooks.py").write_text(f"import sys\nsys.path.insert(0, {str(ROOT / 'tools')!r})\n"
                                       "from docs_hooks import on_page_content\n", encoding="utf-8")
    (tmp_path / "mkdocs.yml").write_text("site_name: t\nstrict: true\nhooks: [hooks.py]\n"
                                         "markdown_extensions:\n  - pymdownx.arithmatex:\n      generic: true\n",
                                         encoding="utf-8")
    proc = _mkdocs_build(tmp_path, tmp_path / "site")
    assert proc.returncode != 0
    assert "index.md: the formula '\\frac{a}{b' does not convert to MathML" in proc.stderr, proc.stderr[-2000:]
    (tmp_path / "docs" / "index.md").write_text("# Formulas\n\nGood $u_2''$.\n", encoding="utf-8")
    proc = _mkdocs_build(tmp_path, tmp_path / "site")
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "<math><msubsup><mi>u</mi>" in _text(tmp_path / "site" / "index.html")


@needs_docs_tools
def test_gallery_page_shows_what_an_example_printed_and_drew(tmp_path):
    script = tmp_path / "tiny.py"
    script.write_text('"""A tiny example.\n\nIt prints and draws."""\nfrom pathlib import Path\nprint("hello")\n'
                      'Path("curve.png").write_bytes(b"png")\n', encoding="utf-8")
    page, images = _hooks().example_page(script, execute=True)
    assert page.startswith("# A tiny example\n") and "It prints and draws." in page
    assert "```text\nhello\n```" in page and "![curve.png](tiny-curve.png)" in page
    assert images == {"tiny-curve.png": b"png"}
    page, images = _hooks().example_page(script, execute=False)
    assert "Not run when this site was built" in page and images == {}


def test_every_page_is_in_the_navigation():
    """Every Markdown page under docs/ is named in mkdocs.yml's navigation (figures/mode-convergence.md was not).

    mkdocs.yml makes a page left out a warning (``validation: nav: omitted_files``), failing the strict build;
    this checks the source without the docs tools. The gallery's pages are generated, and listed by the hooks."""
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8").split("\nnav:", 1)[1]
    named = set(re.findall(r"([\w./-]+\.md)\s*$", nav, flags=re.M))
    pages = {str(p.relative_to(ROOT / "docs")) for p in (ROOT / "docs").rglob("*.md")}
    assert pages and not pages - named, sorted(pages - named)
