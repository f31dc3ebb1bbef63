"""The documentation site renders its equations offline (issue 21): build it strictly, serve it on
localhost and read pages in headless Chromium after MathJax (vendored under docs/javascripts/mathjax/)
ran: every arithmatex span is typeset, none is a MathJax error, the boldsymbol extension works and
the API pages' ``.. math::`` blocks are equations.

Run by ``make test-docs-browser`` (it sets CDPR_DOCS_BROWSER=1; the plain test suite skips it, it
builds the whole site). Skipped, with a message, where no Chromium or Chrome is installed (Debian:
``apt-get install chromium``)."""

import functools
import http.server
import os
import re
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "chrome")

pytestmark = pytest.mark.skipif(
    os.environ.get("CDPR_DOCS_BROWSER") != "1", reason="site build + browser: run `make test-docs-browser`"
)


def _browser():
    for b in BROWSERS:
        if shutil.which(b):
            return shutil.which(b)
    pytest.skip(f"no headless browser installed ({', '.join(BROWSERS)}): `apt-get install chromium`")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1", PYTHONPATH=str(ROOT))
    r = subprocess.run(
        [str(Path(sys.executable).with_name("mkdocs")), "build", "--strict", "-d", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(out))
    handler.log_message = lambda *a, **k: None
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield out, f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()


def rendered(url):
    """The page's DOM after its scripts ran (headless Chromium, JavaScript time budget 20 s)."""
    r = subprocess.run(
        [
            _browser(),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=20000",
            "--dump-dom",
            url,
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return r.stdout


def _spans(dom):
    return re.findall(r'<(span|div) class="arithmatex">(.*?)</\1>', dom, flags=re.S)


def test_the_site_needs_no_cdn(site):
    out, _ = site
    html = (out / "models" / "index.html").read_text(encoding="utf-8")
    assert "cdn.jsdelivr" not in html and "javascripts/mathjax/es5/tex-mml-chtml.js" in html
    assert (
        out / "javascripts" / "mathjax" / "es5" / "input" / "tex" / "extensions" / "boldsymbol.js"
    ).exists()


@pytest.mark.parametrize("page", ["models/", "api/models/"])
def test_math_is_rendered_without_mathjax_errors(site, page):
    _, base = site
    dom = rendered(f"{base}/{page}")
    spans = _spans(dom)
    assert len(spans) > 5, f"{page}: no math on the page"
    raw = [body[:80] for _, body in spans if "<mjx-container" not in body]
    assert raw == [], f"{page}: {len(raw)} equations left as raw TeX, e.g. {raw[:3]}"
    assert "<mjx-merror" not in dom, f"{page}: a MathJax error ({dom[dom.find('<mjx-merror') :][:300]})"
    assert "Undefined control sequence" not in dom


def test_boldsymbol_is_loaded(site):
    _, base = site
    dom = rendered(f"{base}/models/")
    bold = [body for _, body in _spans(dom) if "boldsymbol" in body or 'mathvariant="bold-italic"' in body]
    assert bold, "no \\boldsymbol equation rendered in bold"
    assert all("<mjx-merror" not in b for b in bold)
