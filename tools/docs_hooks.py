"""MkDocs hooks of the documentation site (mkdocs.yml): the home page, the gallery and the formulas.

* ``index.md`` is generated from README.md, its links into docs/ made relative to the site.
* ``reliability.md``: the marker ``<!-- reliability-table: README.md -->`` becomes the README's
  reliability table (kept in the README, where ``tests/test_reliability.py`` compares it).
* ``gallery/``: every ``examples/*.py`` is run at build time, in a temporary folder, with this
  source tree first on ``PYTHONPATH``; its page shows the docstring, the source, what it printed
  and the images it wrote. An example that fails fails the build. ``examples/*.toml`` (sweep
  files) are shown with the command that runs them, not run. ``LUBELINK_DOCS_EXECUTE=0`` builds
  the gallery without running the examples (the pages say so). Each example's page is in the
  navigation, under the gallery's index.
* API pages: the reST roles of the docstrings (``:func:`x```) are shown as plain code.
* Formulas (``$...$``, ``$$...$$``, marked up by ``pymdownx.arithmatex``) are rendered to MathML when
  the site is built (``math-core``), so that a page shows them without a script or a network; a
  formula that does not convert is a warning, which ``strict`` turns into a failed build.
"""

from __future__ import annotations

import ast
import functools
import html
import logging
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from mkdocs.structure.files import File

log = logging.getLogger("mkdocs.hooks.lubelink")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
TIMEOUT = 1800  # [s] per example; the first run compiles the kernels it needs
IMAGE_SUFFIXES = (".png", ".gif", ".svg")


def _execute() -> bool:
    return os.environ.get("LUBELINK_DOCS_EXECUTE", "1") not in ("0", "false", "no")


# --- home page ---------------------------------------------------------------------------------------
_LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)\s]+)\)")


def _site_link(match):
    bang, text, target = match.groups()
    if re.match(r"[a-z]+://|#|mailto:", target):
        return match.group(0)
    if target.startswith("docs/"):
        return f"{bang}[{text}]({target[len('docs/'):]})"
    # a file of the repository outside the site: name it, do not link it
    return f"{text} (`{target}`)" if not bang else f"`{target}`"


def readme_as_index(text: str) -> str:
    """README.md with its links into docs/ relative to the site and other repository links named."""
    return _LINK.sub(_site_link, text)


_TABLE_START, _TABLE_END = "<!-- reliability-table:start -->", "<!-- reliability-table:end -->"
_TABLE_HERE = "<!-- reliability-table: README.md -->"


def reliability_table(readme: str) -> str:
    """The reliability table of README.md, between its markers."""
    if _TABLE_START not in readme or _TABLE_END not in readme:
        raise ValueError("README.md lacks the reliability table markers")
    return readme.split(_TABLE_START, 1)[1].split(_TABLE_END, 1)[0].strip()


# --- gallery -----------------------------------------------------------------------------------------
def run_example(path: Path, timeout: float = TIMEOUT):
    """Run ``path`` in a temporary folder; ``(stdout, {image name: bytes}, seconds)``; raises on failure."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src")] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    env.setdefault("MPLBACKEND", "Agg")
    with tempfile.TemporaryDirectory(prefix="lubelink-gallery-") as tmp:
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, str(path)], cwd=tmp, env=env, capture_output=True, text=True,
                              timeout=timeout)
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            raise RuntimeError(f"gallery: examples/{path.name} failed (exit {proc.returncode}):\n"
                               f"{proc.stdout[-2000:]}\n{proc.stderr[-4000:]}")
        images = {p.name: p.read_bytes() for p in sorted(Path(tmp).iterdir()) if p.suffix in IMAGE_SUFFIXES}
    return proc.stdout, images, seconds


def _title_and_body(doc: str, fallback: str):
    lines = (doc or "").strip().splitlines()
    if not lines:
        return fallback, ""
    return lines[0].rstrip("."), "\n".join(lines[1:]).strip()


def example_page(path: Path, execute: bool):
    """``(markdown, {image name: bytes})`` of the gallery page of one example script."""
    source = path.read_text(encoding="utf-8")
    title, body = _title_and_body(ast.get_docstring(ast.parse(source)), path.stem)
    parts = [f"# {title}", "", f"`examples/{path.name}`", "", body, "", "```python", source.rstrip(), "```", ""]
    images = {}
    if execute:
        out, images, seconds = run_example(path)
        parts += [f"Output (run when this site was built, {seconds:.1f} s including compilation):", "",
                  "```text", out.rstrip() or "(no output)", "```", ""]
        parts += [f"![{name}]({path.stem}-{name})" for name in images]
    else:
        parts += ["*Not run when this site was built (`LUBELINK_DOCS_EXECUTE=0`).*", ""]
    return "\n".join(parts) + "\n", {f"{path.stem}-{name}": data for name, data in images.items()}


def gallery_index(scripts, tomls) -> str:
    parts = ["# Gallery", "",
             "The scripts of `examples/`, run when this site was built (the test suite runs them too,",
             "`tests/test_examples.py`). Run one yourself with `python examples/NAME.py`.", ""]
    for path in scripts:
        title, _ = _title_and_body(ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))), path.stem)
        parts.append(f"* [{title}]({path.stem}.md) (`examples/{path.name}`)")
    if tomls:
        parts += ["", "## Sweep files", "",
                  "Parameter sweeps ([guide](../sweeps.md)); not run here, since a sweep takes minutes on all cores.",
                  ""]
        for path in tomls:
            parts += [f"### `examples/{path.name}`", "", f"`lubelink sweep examples/{path.name}`", "",
                      "```toml", path.read_text(encoding="utf-8").rstrip(), "```", ""]
    return "\n".join(parts) + "\n"


# --- MkDocs events -----------------------------------------------------------------------------------
def on_config(config):
    """Each example's gallery page in the navigation, under the gallery's index (``Gallery:`` in mkdocs.yml)."""
    for i, entry in enumerate(config.nav or []):
        if isinstance(entry, dict) and entry.get("Gallery") == "gallery/index.md":
            pages = [{_title_and_body(ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))), path.stem)[0]:
                      f"gallery/{path.stem}.md"} for path in sorted(EXAMPLES.glob("*.py"))]
            config.nav[i] = {"Gallery": ["gallery/index.md", *pages]}
            return config
    raise ValueError("mkdocs.yml: the navigation lacks the entry 'Gallery: gallery/index.md'")


def on_files(files, config):
    files.append(File.generated(config, "index.md",
                                content=readme_as_index((ROOT / "README.md").read_text(encoding="utf-8"))))
    scripts = sorted(EXAMPLES.glob("*.py"))
    tomls = sorted(EXAMPLES.glob("*.toml"))
    execute = _execute()
    for path in scripts:
        page, images = example_page(path, execute)
        files.append(File.generated(config, f"gallery/{path.stem}.md", content=page))
        for name, data in images.items():
            files.append(File.generated(config, f"gallery/{name}", content=data))
    files.append(File.generated(config, "gallery/index.md", content=gallery_index(scripts, tomls)))
    return files


def on_page_markdown(markdown, page, config, files):
    """The README's reliability table where a page asks for it (docs/reliability.md)."""
    if _TABLE_HERE in markdown:
        markdown = markdown.replace(_TABLE_HERE, reliability_table((ROOT / "README.md").read_text(encoding="utf-8")))
    return markdown


_ROLE = re.compile(r":(?:py:)?(?:func|class|mod|meth|data|attr|exc|obj):(?=<code>)")


def on_page_content(content, page, config, files):
    """Docstrings cross-reference with reST roles; show them as plain code. Formulas become MathML."""
    content = _ROLE.sub("", content)
    content = re.sub(r"<code>~(?=[A-Za-z_])", "<code>", content)
    content, errors = render_formulas(content)
    for error in errors:
        log.warning("%s: %s", page.file.src_uri, error)
    return content


# --- formulas ----------------------------------------------------------------------------------------
# pymdownx.arithmatex (generic): <span class="arithmatex">\(...\)</span> inline,
# <div class="arithmatex">\[...\]</div> displayed, the TeX escaped as HTML
_FORMULA = re.compile(r'<(span|div) class="arithmatex">\s*\\([(\[])(.*?)\\[)\]]\s*</\1>', re.S)


@functools.lru_cache(maxsize=1)
def _converter():
    import math_core

    return math_core.LatexToMathML(fancy_error=False)


def tex_to_mathml(tex: str, display: bool) -> str:
    """``<math>`` of the TeX formula ``tex``; ``ValueError`` naming it where it does not convert."""
    import math_core

    try:
        mathml = _converter().convert_with_local_state(tex, displaystyle=display)
    except math_core.LatexError as error:  # "offset: what", e.g. '0: Unknown command "\foo".'
        raise ValueError(f"the formula '{tex}' does not convert to MathML: {error}") from None
    return _boxes_as_rows(mathml)


_ENCLOSE = re.compile(r"<menclose([^>]*)>|</menclose>")


def _boxes_as_rows(mathml: str) -> str:
    """``\\boxed`` is ``<menclose notation="box">``, which MathML Core (so Chromium) does not draw: an
    ``<mrow class="boxed">`` instead, framed in every browser by docs/stylesheets/math.css."""
    boxes = []  # of each open menclose, whether it is a box

    def rename(match):
        if match.group(0) == "</menclose>":
            return "</mrow>" if boxes.pop() else match.group(0)
        boxes.append('notation="box"' in match.group(1))
        return '<mrow class="boxed">' if boxes[-1] else match.group(0)

    return _ENCLOSE.sub(rename, mathml)


def render_formulas(text: str):
    """``(html, errors)``: the arithmatex formulas of ``text`` as MathML; a formula that does not
    convert stays TeX in ``<code>``, and its error is in ``errors``."""
    errors = []

    def render(match):
        tag, opening, tex = match.groups()
        tex = html.unescape(tex).strip()
        try:
            return f'<{tag} class="arithmatex">{tex_to_mathml(tex, display=opening == "[")}</{tag}>'
        except ValueError as error:
            errors.append(str(error))
            return f'<{tag} class="arithmatex"><code>{html.escape(tex)}</code></{tag}>'

    return _FORMULA.sub(render, text), errors
