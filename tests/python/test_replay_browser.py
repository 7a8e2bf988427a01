"""The replay in a real browser: Debian's chromium, headless, through
selenium and Debian's chromedriver, the network off. The page must load
with no console error and nothing fetched, draw its WebGL scene, and show
the vehicle elsewhere at another slider time.

Without chromium, chromedriver or selenium the test is skipped, unless
NEUROV_REQUIRE_BROWSER=1 (CI sets it), when it fails."""

from __future__ import annotations

import io
import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import neurov
import numpy as np
import pytest
from neurov.config.scenario import scenario_path

BROWSER = shutil.which("chromium") or "/usr/bin/chromium"
DRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
# Headless without a GPU: WebGL through the SwiftShader software renderer,
# which chromium enables only when asked (--enable-unsafe-swiftshader).
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--disable-dev-shm-usage", "--window-size=1000,700", "--hide-scrollbars",
         # The network off twice over: every request goes to a closed port,
         # and (below) the DevTools protocol puts the page offline.
         "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>")


def _missing() -> list[str]:
    import importlib.util

    missing = [path for path in (BROWSER, DRIVER) if not os.access(path, os.X_OK)]
    return missing + [f"the Python package {name}" for name in ("selenium", "plotly")
                      if importlib.util.find_spec(name) is None]


@pytest.fixture(scope="module")
def driver() -> Iterator[Any]:
    missing = _missing()
    if missing:
        why = f"the browser test needs {', '.join(missing)} (Debian: apt-get install chromium chromium-driver)"
        if os.environ.get("NEUROV_REQUIRE_BROWSER") == "1":
            pytest.fail(f"NEUROV_REQUIRE_BROWSER=1 but {why}")
        pytest.skip(why)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = BROWSER
    for flag in FLAGS:
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(DRIVER), options=options)
    try:
        d.set_network_conditions(offline=True, latency=0, download_throughput=0, upload_throughput=0)
        d.set_script_timeout(30)
        yield d
    finally:
        d.quit()


@pytest.fixture(scope="module")
def page(driver: object, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 40 s BlueROV2 helix with thrusters (it moves about 8 m), 12 frames."""
    scenario = neurov.load_scenario(scenario_path("bluerov2_helix"))
    scenario.duration = 40.0
    return neurov.simulate(scenario).view(max_frames=12).write_html(tmp_path_factory.mktemp("replay") / "r.html")


# Shows frame `name`, then waits two animation frames so that WebGL has drawn it.
_SHOW = """
const [name, bodyVisible, done] = arguments;
const gd = document.querySelector('.plotly-graph-div');
const body = gd.data.findIndex(t => t.type === 'mesh3d');
Plotly.animate(gd, [name], {frame: {duration: 0, redraw: true}, mode: 'immediate', transition: {duration: 0}})
  .then(() => Plotly.restyle(gd, {visible: bodyVisible}, [body]))
  .then(() => requestAnimationFrame(() => requestAnimationFrame(() =>
        done(document.querySelector('.gtitle').textContent))))
  .catch(e => done('error: ' + e));
"""


def _shot(driver: Any, frame: str, body: bool = True) -> tuple[np.ndarray, str]:
    from PIL import Image

    title = driver.execute_async_script(_SHOW, frame, body)
    assert not title.startswith("error"), title
    png = Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB")
    return np.asarray(png, dtype=np.int16), title


def _changed(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b).sum(axis=2) > 30


def _severe(driver: Any) -> list[dict[str, Any]]:
    return [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def test_the_replay_plays_offline_in_chromium(driver: Any, page: Path) -> None:
    html = page.read_text(encoding="utf-8")
    assert "<script src" not in html  # plotly.js is inside the file
    driver.get(page.as_uri())
    frames = driver.execute_script(
        "return document.querySelector('.plotly-graph-div')._transitionData._frames.length")
    assert frames == 12
    last = str(frames - 1)

    start, start_title = _shot(driver, "0")
    rect = "const r = document.querySelector(arguments[0]).getBoundingClientRect(); " \
           "return [r.left, r.top, r.width, r.height].map(Math.round)"
    x, y, w, h = driver.execute_script(rect, ".gl-container canvas")
    lx, ly, lw, lh = driver.execute_script(rect, ".legend")  # with the body's entry
    start_bare, _ = _shot(driver, "0", body=False)
    end, end_title = _shot(driver, last)
    end_bare, _ = _shot(driver, last, body=False)

    if os.environ.get("NEUROV_REPLAY_SHOTS"):  # a folder to look at the screenshots in
        from PIL import Image

        for name, shot in (("start", start), ("start_bare", start_bare), ("end", end), ("end_bare", end_bare)):
            Image.fromarray(shot.astype(np.uint8)).save(Path(os.environ["NEUROV_REPLAY_SHOTS"]) / f"{name}.png")

    # The WebGL scene is drawn: the canvas is not blank.
    scene = start[y:y + h, x:x + w]
    assert w > 300 and h > 300
    assert (scene != 255).any(axis=2).mean() > 0.1  # the axes' panes (light grey) at least
    assert (np.abs(scene - 255).sum(axis=2) > 30).mean() > 0.01  # the paths, the grid, the body
    assert len(np.unique(scene.reshape(-1, 3), axis=0)) > 50  # shaded, not a flat fill

    # Where the body is at each time: what hiding it changes in the scene
    # (its legend entry goes too: the legend is left out).
    inside = np.zeros(start.shape[:2], dtype=bool)
    inside[y:y + h, x:x + w] = True
    inside[max(ly - 5, 0):ly + lh + 5, max(lx - 5, 0):lx + lw + 5] = False
    at_start, at_end = _changed(start, start_bare) & inside, _changed(end, end_bare) & inside
    assert at_start.sum() > 100 and at_end.sum() > 100
    centres = [np.argwhere(m).mean(axis=0) for m in (at_start, at_end)]
    assert np.linalg.norm(centres[0] - centres[1]) > 40  # pixels: the vehicle moved on the screen
    # The two slider times' pictures differ there (the body left its start
    # and arrived at its end), and the caption tells the time and depth.
    differ = _changed(start, end)
    assert differ[at_start].mean() > 0.5 and differ[at_end].mean() > 0.5
    assert "t = 0.0 s" in start_title and "t = 40.0 s" in end_title
    assert "depth: NN adaptive" in end_title and start_title != end_title

    # Play runs the frames on from the slider's place.
    title = "return document.querySelector('.gtitle').textContent"
    _shot(driver, "0")
    next(b for b in driver.find_elements("css selector", ".updatemenu-button") if b.text.strip() == "Play").click()
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(driver, 10, poll_frequency=0.1).until(lambda d: d.execute_script(title) != start_title)

    # Nothing but the page itself was loaded, and the console has no error.
    fetched = driver.execute_script("return performance.getEntriesByType('resource').map(e => e.name)")
    assert [u for u in fetched if not u.startswith(("file:", "data:", "blob:"))] == []
    assert _severe(driver) == []
    # And the network is off: a request that would succeed online fails.
    probe = "https://cdn.plot.ly/plotly-latest.min.js"
    reached = driver.execute_async_script(
        f"const done = arguments[0]; fetch('{probe}').then(() => done(true), () => done(false));")
    assert reached is False
    assert all(probe in e["message"] for e in _severe(driver))
