"""Checks impactsweep's HTML pages in a real headless Chromium (issue 18), driven by Selenium
through Debian's chromium-driver.

    python tests/html_check.py ROOT [--screenshot PNG [--shot-study NAME]] [--negative]

ROOT is an output root (ideally a copy in another directory, which proves the pages need
nothing outside it). From ROOT/index.html every link and image must resolve to a file under
ROOT and load; every page must load with no console error and no failed or non-file request;
every chart must be drawn (a non-empty SVG; a map has one cell per grid point of its pair of
axes, a design chart one point per value of its axis); every hover value (`data-*` and
`<title>` of each design point) must agree with the study's summary.parquet read by pyarrow;
hovering the recommended design's cell must show its values; clicking a zone row must
highlight that zone's cells. `--negative` then breaks copies of ROOT (an empty chart, a broken
link, a script error) and fails unless the check rejects each. Exit 0 when all is well.
"""

import argparse
import json
import math
import os
import re
import shutil
import sys
import tempfile
from pathlib import Path
from urllib.parse import unquote, urlparse

import pyarrow.parquet as pq
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.actions.action_builder import ActionBuilder
from selenium.webdriver.common.by import By

CHROMEDRIVER = os.environ.get("CHROMEDRIVER", "/usr/bin/chromedriver")
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")


class PageError(Exception):
    pass


def browser(profile_dir):
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in [
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--hide-scrollbars",
        "--window-size=1280,1000",
        f"--user-data-dir={profile_dir}",
    ]:
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)


def load(drv, path):
    """Loads a page by file:// URL; raises on console errors and failed or non-file requests."""
    drv.get_log("browser")
    drv.get_log("performance")
    drv.get(path.resolve().as_uri())
    drv.execute_script("return document.readyState")
    problems = []
    for e in drv.get_log("browser"):
        if e.get("level") == "SEVERE":
            problems.append(f"console error: {e.get('message')}")
    # The requests our pages made (the browser's own pages, its new-tab page, are not ours).
    ours = {}
    for e in drv.get_log("performance"):
        msg = json.loads(e["message"])["message"]
        method, params = msg.get("method"), msg.get("params", {})
        if method == "Network.requestWillBeSent":
            if not params.get("documentURL", "").startswith("file://"):
                continue
            url = params.get("request", {}).get("url", "")
            ours[params.get("requestId")] = url
            if not (url.startswith("file://") or url.startswith("data:") or url == "about:blank"):
                problems.append(f"request to {url}")
        elif method == "Network.loadingFailed" and params.get("requestId") in ours:
            problems.append(
                f"failed request: {ours[params.get('requestId')]}: {params.get('errorText')}"
            )
    # Resources the page names: none outside the file system, none missing.
    refs = drv.execute_script(
        """
        const out = [];
        document.querySelectorAll('[src],[href],[*|href]').forEach(el => {
          for (const a of ['src', 'href', 'xlink:href']) {
            const v = el.getAttribute(a);
            if (v !== null) out.push([el.tagName, v]);
          }
        });
        document.querySelectorAll('img').forEach(im => {
          if (!(im.complete && im.naturalWidth > 0)) out.push(['BROKEN-IMG', im.getAttribute('src')]);
        });
        return out;"""
    )
    for tag, v in refs:
        if tag == "BROKEN-IMG":
            problems.append(f"image not loaded: {v}")
        elif re.match(r"^[a-z][a-z0-9+.-]*:", v, re.I) and not v.startswith("data:"):
            problems.append(f"{tag} refers to {v} (only relative links are allowed)")
    if problems:
        raise PageError(f"{path}: " + "; ".join(problems))


def links(drv, page):
    """The relative links and images of the loaded page, resolved against its file."""
    hrefs = drv.execute_script(
        "return [...document.querySelectorAll('a[href]')].map(a => a.getAttribute('href'))"
        ".concat([...document.querySelectorAll('img[src]')].map(i => i.getAttribute('src')))"
    )
    out = []
    for h in hrefs:
        if h.startswith("#"):
            if not drv.execute_script("return !!document.getElementById(arguments[0])", h[1:]):
                raise PageError(f"{page}: link {h} has no target")
            continue
        target = (page.parent / unquote(urlparse(h).path)).resolve()
        if not target.is_file():
            raise PageError(f"{page}: link {h} does not resolve ({target} missing)")
        out.append(target)
    return out


def num_equal(attr, value):
    if value is None:
        return attr == ""
    if isinstance(value, bool):
        return attr == ("true" if value else "false")
    if isinstance(value, float):
        if attr == "":
            return math.isnan(value)
        a = float(attr)
        return (math.isnan(a) and math.isnan(value)) or a == value
    if isinstance(value, int):
        return attr != "" and int(attr) == value
    return attr == str(value)


def check_report(drv, page):
    """A report page: charts drawn, hover values = summary.parquet, hover and zone click."""
    summary = pq.read_table(page.parent / "summary.parquet").to_pylist()
    by_point = {r["point"]: r for r in summary}
    charts = drv.execute_script(
        """
        return [...document.querySelectorAll('figure.chart')].map(f => {
          const s = f.querySelector('svg');
          return {id: f.id, svg: !!s,
            shapes: s ? s.querySelectorAll('rect,path,circle,line,polyline,polygon,text').length : 0,
            kind: s ? s.getAttribute('class') : null,
            axes: s ? s.getAttribute('data-axes') : null,
            cells: s ? s.querySelectorAll('rect.cell').length : 0,
            pts: s ? s.querySelectorAll('g.pt').length : 0,
            declared: s ? s.getAttribute('data-cells') || s.getAttribute('data-points') : null,
            w: s ? s.getBoundingClientRect().width : 0, h: s ? s.getBoundingClientRect().height : 0};
        });"""
    )
    if not charts:
        raise PageError(f"{page}: no chart")
    for c in charts:
        if not c["svg"] or c["shapes"] < 5 or c["w"] < 50 or c["h"] < 50:
            raise PageError(f"{page}: chart {c['id']} is empty ({c})")
        if c["kind"] in ("map", "profile"):
            axes = c["axes"].split()
            expected = 1
            for a in axes:
                expected *= len({r[a] for r in summary})
            got = c["cells"] if c["kind"] == "map" else c["pts"]
            if got != expected or str(got) != c["declared"]:
                raise PageError(
                    f"{page}: chart {c['id']} draws {got} design points, expected {expected}"
                )
    points = drv.execute_script(
        """
        return [...document.querySelectorAll('[data-point]')].map(el => {
          const d = {};
          for (const a of el.attributes) if (a.name.startsWith('data-')) d[a.name.slice(5)] = a.value;
          const t = el.querySelector(':scope > title');
          return [d, t ? t.textContent : null];
        });"""
    )
    if not points:
        raise PageError(f"{page}: no design point carries its data")
    for d, title in points:
        row = by_point.get(int(d["point"]))
        if row is None:
            raise PageError(f"{page}: design point {d['point']} is not in summary.parquet")
        for k, v in d.items():
            if k in ("merged", "recommended"):
                continue
            if k not in row:
                raise PageError(f"{page}: data-{k} is not a summary column")
            if not num_equal(v, row[k]):
                raise PageError(
                    f"{page}: point {d['point']}: data-{k} = {v}, summary.parquet has {row[k]}"
                )
        r = row["reliability"]
        want = [f"design point {row['point']}", f"class: {row['class']}"]
        if r is not None and not math.isnan(r):
            want.append(f"R = {r:.5f}")
        if row["zone"]:
            want.append(f"zone {row['zone']}: ")
        if row["rank"] is not None:
            want.append(f"rank {row['rank']:,} of")
        missing = [w for w in want if title is None or w not in title]
        if missing:
            raise PageError(f"{page}: point {d['point']}: hover text {title!r} lacks {missing}")
    text = drv.execute_script("return document.querySelector('main, body').innerText")
    # A single `*` after a number is the stripes table's marker (a lognormal outside the
    # stripe's interval), not emphasis.
    stray = re.search(r"(?:^|\s)\*+\w|(?:[^\W\d]\*+|\w\*\*+)(?:\s|$|[.,;:)])", text)
    if stray:
        raise PageError(f"{page}: Markdown emphasis shown literally: ...{text[max(0, stray.start() - 40):stray.end() + 40]!r}...")
    hover(drv, page, by_point)
    forced_hovers(drv, page)
    zone_click(drv, page)
    return len(points), len(charts)


FORCED_CHARTS = ("fig-frequency_response", "fig-branches", "fig-basin_shares")


def forced_hovers(drv, page):
    """The forced charts' points (frequency response, branches, basin shares) carry hover
    texts: each such figure has targets whose <title> names the frequency, and hovering one
    shows that text beside the pointer."""
    figs = drv.execute_script(
        """
        return [...document.querySelectorAll('figure.chart')].filter(f =>
            arguments[0].some(p => f.id.startsWith(p))).map(f => [f.id,
            [...f.querySelectorAll('[data-hover]')].map(el => {
              const t = el.querySelector(':scope > title');
              return t ? t.textContent : null;
            })]);""",
        list(FORCED_CHARTS),
    )
    for fid, titles in figs:
        if not titles or any(t is None or "r = " not in t for t in titles):
            raise PageError(f"{page}: chart {fid} has {len(titles)} hover targets, each needs a text naming r")
    for prefix in FORCED_CHARTS:
        els = drv.find_elements(By.CSS_SELECTOR, f'figure.chart[id^="{prefix}"] [data-hover]')
        if not els:
            continue
        el = els[len(els) // 2]
        drv.execute_script("arguments[0].scrollIntoView({block: 'center'})", el)
        # Targets of neighbouring curves can overlap: the one under the pointer is the one
        # whose text must show. The pointer goes to a whole pixel near the target's centre and
        # the page is asked what lies under that same pixel (Selenium's own centre of an SVG
        # element can be half a pixel off the bounding box's, and on the neighbour there).
        x, y = drv.execute_script(
            """
            const r = arguments[0].getBoundingClientRect();
            return [Math.floor(r.x + r.width / 2), Math.floor(r.y + r.height / 2)];""",
            el,
        )
        pointer = ActionBuilder(drv)
        pointer.pointer_action.move_to_location(x, y)
        pointer.perform()
        want = drv.execute_script(
            """
            const top = document.elementFromPoint(arguments[0], arguments[1]);
            const t = top && top.closest('[data-hover]');
            const title = t && t.querySelector(':scope > title');
            return title ? title.textContent : null;""",
            x,
            y,
        )
        tip = drv.find_element(By.ID, "tip")
        if want is None or not tip.is_displayed() or tip.get_attribute("textContent") != want:
            raise PageError(f"{page}: hovering a point of {prefix} shows {tip.text!r}, not {want!r}")


def hover(drv, page, by_point):
    cells = drv.find_elements(By.CSS_SELECTOR, "svg.map rect.cell[data-recommended]")
    if not cells:
        cells = drv.find_elements(By.CSS_SELECTOR, "g.pt[data-recommended] circle.r")
    if not cells:
        if drv.find_elements(By.CSS_SELECTOR, "[data-recommended]"):
            raise PageError(f"{page}: the recommended design is not on any chart to hover")
        return
    el = cells[0]
    drv.execute_script("arguments[0].scrollIntoView({block: 'center'})", el)
    ActionChains(drv).move_to_element(el).perform()
    tip = drv.find_element(By.ID, "tip")
    text = tip.text
    if not tip.is_displayed() or "the recommended design" not in text:
        raise PageError(f"{page}: hovering the recommended design shows {text!r}")
    point = int(el.get_attribute("data-point") or el.find_element(By.XPATH, "..").get_attribute("data-point"))
    row = by_point[point]
    for w in (f"R = {row['reliability']:.5f}", f"zone {row['zone']}", f"design point {point}"):
        if w not in text:
            raise PageError(f"{page}: hover text {text!r} lacks {w!r}")


def zone_click(drv, page):
    rows = drv.find_elements(By.CSS_SELECTOR, "tr.zone-row")
    if not rows or not drv.find_elements(By.CSS_SELECTOR, "svg rect.cell"):
        return
    zone = None
    for tr in rows:
        z = tr.get_attribute("data-zone")
        if drv.find_elements(By.CSS_SELECTOR, f'svg rect.cell[data-zone="{z}"]'):
            zone = tr
            break
    if zone is None:
        return
    drv.execute_script("arguments[0].scrollIntoView({block: 'center'})", zone)
    zone.click()
    z = zone.get_attribute("data-zone")
    lit = drv.execute_script(
        "return [...document.querySelectorAll('.hl')].map(e => e.getAttribute('data-zone'))"
    )
    if not lit or any(x != z for x in lit):
        raise PageError(f"{page}: clicking zone {z} highlights {len(lit)} cells of zones {set(lit)}")
    zone.click()
    if drv.find_elements(By.CSS_SELECTOR, ".hl"):
        raise PageError(f"{page}: clicking zone {z} again does not clear the highlight")


def check_root(drv, root, screenshot=None, shot_study=None):
    """Every page of the output root; returns what was checked."""
    index = root / "index.html"
    if not index.is_file():
        raise PageError(f"{index} missing")
    load(drv, index)
    studies = drv.execute_script(
        "return [...document.querySelectorAll('tr[data-study]')].map(r => r.getAttribute('data-study'))"
    )
    targets = links(drv, index)
    pages = [t for t in targets if t.suffix == ".html"]
    done = {"index": str(index), "studies": studies, "reports": {}}
    for page in pages:
        load(drv, page)
        links(drv, page)
        n_points, n_charts = check_report(drv, page)
        done["reports"][page.parent.name] = {"points": n_points, "charts": n_charts}
    missing = [s for s in studies if s not in done["reports"]]
    for s in missing:
        if (root / s / "report.html").is_file():
            raise PageError(f"{index}: study {s} has a report.html the index does not link")
    if screenshot:
        page = root / (shot_study or pages[0].parent.name) / "report.html"
        load(drv, page)
        drv.set_window_size(1280, 900)
        # The zone map over e and d (else the first zone map), its recommended design hovered.
        el = drv.find_elements(
            By.CSS_SELECTOR, 'svg.map[data-kind="zones"][data-axes="e d"] rect.cell[data-recommended]'
        ) or drv.find_elements(By.CSS_SELECTOR, 'svg.map[data-kind="zones"] rect.cell[data-recommended]')
        if el:
            fig = el[0].find_element(By.XPATH, "ancestor::figure")
            drv.execute_script("arguments[0].scrollIntoView({block: 'start'})", fig)
            ActionChains(drv).move_to_element(el[0]).perform()
        drv.save_screenshot(str(screenshot))
        done["screenshot"] = str(screenshot)
    return done


def negative(drv, root):
    """Broken copies of the root must be rejected."""
    html_pages = sorted(root.glob("*/report.html"))
    if not html_pages:
        raise PageError("no report.html to break")
    victim = html_pages[0].parent.name
    breakers = {
        "an empty chart": lambda r: edit(
            r / victim / "report.html",
            lambda t: re.sub(r"(<figure class=\"chart\"[^>]*>\s*(?:<figcaption>.*?</figcaption>\s*)?<div class=\"svg\">)<svg.*?</svg>",
                             r'\1<svg class="x" width="400" height="300"></svg>', t, count=1, flags=re.S),
        ),
        "a missing map cell": lambda r: edit(
            r / victim / "report.html",
            lambda t: re.sub(r"<rect class=\"cell\"[^>]*>.*?</rect>", "", t, count=1, flags=re.S),
        ) if "class=\"cell\"" in (r / victim / "report.html").read_text() else edit(
            r / victim / "report.html",
            lambda t: re.sub(r"<g class=\"pt\".*?</g>", "", t, count=1, flags=re.S),
        ),
        "a broken link": lambda r: (r / victim / "report.html").rename(r / victim / "report.old"),
        "a script error": lambda r: edit(
            r / victim / "report.html", lambda t: t.replace("</body>", "<script>notAFunction();</script></body>")
        ),
        "a network request": lambda r: edit(
            r / victim / "report.html",
            lambda t: t.replace("</body>", '<img src="http://127.0.0.1:9/x.png" alt=""></body>'),
        ),
        "a hover value off summary.parquet": lambda r: edit(
            r / victim / "report.html",
            # R on a laboratory page, p_f on a load study's (whose R is empty).
            lambda t: re.sub(r'data-(reliability|p_f)="([0-9.]+)"',
                             lambda m: f'data-{m.group(1)}="{float(m.group(2)) / 2}"', t, count=1),
        ),
    }
    caught = {}
    for what, brk in breakers.items():
        with tempfile.TemporaryDirectory() as tmp:
            copy = Path(tmp) / "out"
            shutil.copytree(root, copy)
            brk(copy)
            try:
                check_root(drv, copy)
            except PageError as e:
                caught[what] = str(e)[:200]
                continue
            raise SystemExit(f"negative check: a copy with {what} passed the check")
    return caught


def edit(path, f):
    text = path.read_text()
    new = f(text)
    if new == text:
        raise SystemExit(f"negative check: could not break {path}")
    path.write_text(new)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("root", type=Path)
    ap.add_argument("--screenshot", type=Path)
    ap.add_argument("--shot-study")
    ap.add_argument("--negative", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as profile:
        drv = browser(profile)
        try:
            try:
                done = check_root(drv, args.root, args.screenshot, args.shot_study)
            except PageError as e:
                print(f"FAIL: {e}", file=sys.stderr)
                return 1
            if args.negative:
                done["negative"] = negative(drv, args.root)
        finally:
            drv.quit()
    print(json.dumps(done, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
