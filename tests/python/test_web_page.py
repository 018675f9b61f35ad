"""The web page of `brdfbake serve` (docs/SERVICE.md, "The web page") in a real browser: Debian's
chromium and chromium-driver (scripts/deps.sh), driven by Selenium (python/requirements-test.txt),
headless, against a server on 127.0.0.1 with a token and an input root. Every wait is bounded
(WAIT_S). Skips with a message where chromium, its driver or Selenium is missing."""

import base64
import json
import os
import pathlib
import re
import shutil
import subprocess
import tarfile
import time
import urllib.error
import urllib.request

import pytest

WAIT_S = 60  # the longest any step may take: a draft bake of a 1k HDR takes a few seconds
TOKEN = "web-page-test-token-0123456789"
HDR = "venice_sunset_1k.hdr"


def _find(*names):
    for n in names:
        path = shutil.which(n) or (f"/usr/bin/{n}" if os.access(f"/usr/bin/{n}", os.X_OK) else None)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def browser_paths():
    try:
        import selenium  # noqa: F401
    except ImportError:
        pytest.skip("selenium is not installed (python/requirements-test.txt; scripts/test.sh installs it)")
    chromium = _find("chromium", "chromium-browser")
    driver = _find("chromedriver")
    if not chromium or not driver:
        pytest.skip("chromium and chromium-driver are not installed (scripts/deps.sh installs them)")
    return chromium, driver


@pytest.fixture(scope="module")
def server(cli, shared_dir, tmp_path_factory):
    """`brdfbake serve` on a free loopback port, with a token and an input root holding a shared HDR
    (copied: the root refuses links that leave it) and a file that is not an image."""
    if shared_dir is None or not (shared_dir / "envmaps" / HDR).is_file():
        pytest.skip(f"the shared HDR maps are not here (../shared/envmaps/{HDR}; BRDFBAKE_SHARED_DIR)")
    base = tmp_path_factory.mktemp("web")
    inputs = base / "inputs"
    inputs.mkdir()
    shutil.copy(shared_dir / "envmaps" / HDR, inputs / HDR)
    (inputs / "broken.hdr").write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 8\n" + b"\x01" * 7)
    (base / "token").write_text(TOKEN + "\n")
    url_file = base / "url"
    log = open(base / "server.log", "w")
    proc = subprocess.Popen(
        [cli, "serve", "--listen", "127.0.0.1:0", "--url-file", str(url_file), "--data", str(base / "data"),
         "--input-root", str(inputs), "--token-file", str(base / "token")],
        stdout=log, stderr=subprocess.STDOUT)
    deadline = time.monotonic() + WAIT_S
    while not (url_file.exists() and url_file.read_text().endswith("\n")):
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            pytest.fail("brdfbake serve did not start: " + (base / "server.log").read_text())
        time.sleep(0.05)
    yield {"url": url_file.read_text().strip(), "inputs": inputs, "base": base}
    # Stopped before its folder goes (at the session's end, conftest.py).
    proc.terminate()
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    log.close()
    proc.terminate()
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    log.close()


@pytest.fixture(scope="module")
def browser(browser_paths, tmp_path_factory):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    chromium, driver = browser_paths
    downloads = tmp_path_factory.mktemp("downloads")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1400,1000",
                "--no-first-run", "--disable-extensions", "--disable-background-networking",
                f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}"):
        options.add_argument(arg)
    if os.geteuid() == 0:
        options.add_argument("--no-sandbox")  # chromium refuses to run as root with its sandbox
    options.add_experimental_option("prefs", {"download.default_directory": str(downloads),
                                              "download.prompt_for_download": False})
    d = webdriver.Chrome(options=options, service=Service(executable_path=driver))
    d.set_page_load_timeout(WAIT_S)
    d.set_script_timeout(WAIT_S)
    d.downloads = downloads
    yield d
    d.quit()


def _wait(driver, condition, what):
    from selenium.common.exceptions import TimeoutException
    from selenium.webdriver.support.ui import WebDriverWait

    try:
        return WebDriverWait(driver, WAIT_S, poll_frequency=0.05).until(condition)
    except TimeoutException:
        # What the page showed, to tell why.
        shown = driver.execute_script(
            "return ['server-status', 'token-error', 'bake-error', 'job-state', 'job-error']"
            ".map(id => id + ': ' + document.getElementById(id).textContent).join('; ')")
        pytest.fail(f"not {what} within {WAIT_S} s; the page showed {shown}")


def _shot(driver, name):
    """With BRDFBAKE_WEB_SCREENSHOTS=DIR, a screenshot of the whole page (docs/SERVICE.md's pictures)."""
    folder = os.environ.get("BRDFBAKE_WEB_SCREENSHOTS")
    if folder:
        height = driver.execute_script("return document.documentElement.scrollHeight")
        driver.set_window_size(1280, min(max(height, 600), 4000))
        driver.save_screenshot(os.path.join(folder, f"web_{name}.png"))
        driver.set_window_size(1400, 1000)


def _text(driver, element_id):
    return driver.find_element("id", element_id).text


def _login(driver, url):
    """Loads the page and gives it the token (once per tab: sessionStorage keeps it)."""
    driver.get(url + "/")
    _wait(driver, lambda d: d.execute_script(
        "return document.body.dataset.ready === 'true' || !document.getElementById('token-section').hidden"),
        "the page asks for the token or is ready")
    if driver.execute_script("return document.body.dataset.ready") != "true":
        token = driver.find_element("id", "token")
        token.clear()
        token.send_keys(TOKEN)
        driver.find_element("css selector", "#token-form button[type=submit]").click()
        _wait(driver, lambda d: d.execute_script("return document.body.dataset.ready === 'true'"), "the page ready")


def _set(driver, name, value):
    """Sets an option's control as a user would (typing into it, or choosing from its list)."""
    from selenium.webdriver.support.ui import Select

    e = driver.find_element("id", "opt-" + name)
    if e.tag_name == "select":
        Select(e).select_by_value(value)
    else:
        e.clear()
        e.send_keys(value)


def _http(url, token=None):
    req = urllib.request.Request(url, headers={"Authorization": f"Bearer {token}"} if token else {})
    try:
        with urllib.request.urlopen(req, timeout=WAIT_S) as r:
            return r.status, dict(r.headers), r.read()
    except urllib.error.HTTPError as e:
        return e.code, dict(e.headers), e.read()


def test_page_is_served_without_the_token_and_holds_no_data(server):
    url = server["url"]
    total = 0
    for path, kind in (("/", "text/html"), ("/app.js", "text/javascript"), ("/app.css", "text/css")):
        status, headers, body = _http(url + path)
        assert status == 200, path
        assert headers["Content-Type"].startswith(kind), path
        assert "default-src 'self'" in headers["Content-Security-Policy"]
        assert headers["X-Content-Type-Options"] == "nosniff"
        # Nothing of the server's state: no input name, no job, no token.
        assert HDR.encode() not in body and TOKEN.encode() not in body
        total += len(body)
    assert total <= 300 * 1024  # the page weight before any result image
    # The API the page calls still needs the token.
    for path in ("/v1/health", "/v1/inputs", "/v1/bake/options", "/v1/kinds"):
        assert _http(url + path)[0] == 401, path
    status, _, body = _http(url + "/v1/inputs", TOKEN)
    assert status == 200 and HDR in [e["path"] for e in json.loads(body)["environments"]]


def test_wrong_token_is_refused_with_the_message_shown(server, browser):
    browser.delete_all_cookies()
    browser.get(server["url"] + "/")
    browser.execute_script("sessionStorage.clear()")
    browser.get(server["url"] + "/")
    _wait(browser, lambda d: d.find_element("id", "token-section").get_attribute("hidden") is None, "the token form")
    browser.find_element("id", "token").send_keys("not-the-token-of-this-server")
    browser.find_element("css selector", "#token-form button[type=submit]").click()
    _wait(browser, lambda d: _text(d, "token-error") != "", "the refusal shown")
    assert "missing or wrong bearer token" in _text(browser, "token-error")
    _shot(browser, "token")
    assert browser.find_element("id", "bake-section").get_attribute("hidden") is not None
    assert browser.execute_script("return sessionStorage.getItem('brdfbake-token')") is None
    _login(browser, server["url"])  # the right one is taken
    assert browser.execute_script("return sessionStorage.getItem('brdfbake-token')") == TOKEN


def test_bad_inputs_show_the_api_error_next_to_the_field(server, browser):
    _login(browser, server["url"])
    # Refused at submission: a path that leaves the input root.
    _set(browser, "environment", "../token")
    browser.find_element("id", "bake-button").click()
    _wait(browser, lambda d: _text(d, "error-environment") != "", "the error next to the environment")
    assert _text(browser, "error-environment") == "bake: environment: '../token' must stay inside the input root (no '..')"
    # Refused when read: a file that is not a Radiance image; the failed job's line, by the field.
    _set(browser, "environment", "broken.hdr")
    browser.find_element("id", "bake-button").click()
    _wait(browser, lambda d: _text(d, "job-state") == "failed", "the job failed")
    message = _text(browser, "error-environment")
    assert "cannot read environment" in message and "broken.hdr" in message and "\n" not in message
    # A number out of its range, in the generated options.
    browser.find_element("css selector", "#more-options summary").click()
    _set(browser, "environment", HDR)
    _set(browser, "chain_size", "-1")
    browser.find_element("id", "plan-button").click()
    _wait(browser, lambda d: _text(d, "error-chain_size") != "", "the error next to chain_size")
    assert _text(browser, "error-chain_size") == "bake: chain_size: must be an integer in 1..2048 (got -1)"
    assert _text(browser, "error-environment") == ""
    _shot(browser, "error")


PIXELS_JS = """
const out = [];
for (const img of document.querySelectorAll('#results img')) {
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  let variance = 0;
  if (img.naturalWidth > 0) {
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const p = g.getImageData(0, 0, c.width, c.height).data;
    let s = 0, s2 = 0, n = 0;
    for (let i = 0; i < p.length; i += 4) { const v = p[i] + p[i + 1] + p[i + 2]; s += v; s2 += v * v; ++n; }
    variance = s2 / n - (s / n) * (s / n);
  }
  out.push({alt: img.alt, width: img.naturalWidth, height: img.naturalHeight, variance: variance, complete: img.complete});
}
return out;
"""


def test_bake_a_shared_hdr_for_filament_look_and_download(server, browser, cli, tmp_path):
    _login(browser, server["url"])
    _set(browser, "environment", HDR)
    _set(browser, "target", "filament")
    browser.find_element("id", "preset-draft").click()
    assert browser.find_element("id", "opt-chain_size").get_attribute("value") == "64"
    browser.find_element("id", "copy-command").click()
    command = _text(browser, "command-text")
    assert command.startswith("brdfbake bake ") and f"--environment {HDR}" in command and "--target filament" in command
    # The canonical names (issue 34), never the old ones.
    assert "--chain-size 64" in command and "--chain-max-error 0.05" in command, command
    assert "--cube-size" not in command and "--prefilter-max-error" not in command, command
    # The dry run: each table's estimated time on the server's device and the bytes of its files
    # (POST /v1/plan, measured by bakes at reduced size), and the whole bake's.
    browser.find_element("id", "plan-button").click()
    _wait(browser, lambda d: _text(d, "plan-total").startswith("Whole bake: about"), "the dry run's estimate")
    rows = browser.find_elements("css selector", "#plan-table tbody tr")
    assert len(rows) >= 2  # filament: the chain and the SH (it samples its own DFG table: none baked)
    for row in rows:
        cells = [c.text for c in row.find_elements("css selector", "td")]
        assert re.fullmatch(r"\d+\.\d\d s", cells[2]), cells
        assert re.fullmatch(r"\d+(\.\d)? (B|KiB|MiB)", cells[3]), cells
    _shot(browser, "dry_run")

    browser.find_element("id", "bake-button").click()
    _wait(browser, lambda d: d.execute_script("return document.getElementById('results').dataset.ready === 'true'"),
          "the bake done and its pictures shown")
    assert _text(browser, "job-state") == "done"
    seconds = float(browser.execute_script("return document.getElementById('results').dataset.seconds"))
    job_id = _text(browser, "job-id")
    print(f"web page: Bake to every picture shown in {seconds:.2f} s (job {job_id})")
    _shot(browser, "result")
    # Every bar at 100 %.
    bars = browser.execute_script("return [...document.querySelectorAll('#job-progress progress')].map(p => p.value)")
    assert bars and all(v == 100 for v in bars)

    # Every table of the manifest has its picture, decoded and not blank.
    status, _, body = _http(f"{server['url']}/v1/jobs/{job_id}", TOKEN)
    manifest = json.loads(body)["manifest"]
    figures = json.loads(body)["error_figures"]
    pictures = browser.execute_script(PIXELS_JS)
    # ... and Filament's KTX1 cubes (the IBL and the skybox), which `brdfbake view` reads too.
    ktx = [p for p in manifest.get("engine", {}).get("files", []) if p.endswith(".ktx")]
    assert len(ktx) == 2, manifest.get("engine")
    assert len(pictures) == len(manifest["files"]) + len(ktx) >= 4  # filament: the chain and the SH, two KTX1
    for p in pictures:
        assert p["complete"] and p["width"] > 0 and p["height"] > 0, p
        assert p["variance"] > 0, p
    # Each file's delivered bound is shown as the command line prints it (error_bound_text): at
    # most three significant digits, rounded up, never below the manifest's bound.
    for f in manifest["files"]:
        shown = browser.find_element("css selector", f"#results div.file[data-path='{f['path']}'] p").text
        # under the figure's name, as the manifest names it (docs/CONVENTIONS.md, "Error figures")
        name = f["error_name"]
        bound = re.search(re.escape(name) + r" (\S+)", shown).group(1)
        assert figures[f["path"]]["error_name"] == name
        if f.get(name) is not None:
            assert bound == figures[f["path"]][name], shown
            assert float(bound) >= f[name], shown
            assert len(re.sub(r"e.*$", "", bound).replace("0.", "").lstrip("0").replace(".", "")) <= 3, shown
        else:
            assert bound == "—", shown
    # Each engine file with its size and delivered error (the manifest's engine.file_entries, issue 35):
    # the page prints the figures the manifest records, under their names.
    entries = {e["path"]: e for e in manifest["engine"]["file_entries"]}
    for p in manifest["engine"]["files"]:
        shown = browser.find_element("css selector", f"#results div.file[data-path='{p}'] p").text
        e = entries[p]
        if e["error_rms_rel"] is None:
            assert "no texel values" in shown, shown
        else:
            rms = float(re.search(r"error_rms_rel (\S+),", shown).group(1))
            assert rms == pytest.approx(e["error_rms_rel"], rel=0.05), shown
            assert "error_max_rel" in shown and e["format"] in shown, shown

    # A download is byte for byte the file the command line writes for the same job.
    browser.find_element("id", "copy-result-job").click()  # fetched, then shown: wait for it
    _wait(browser, lambda d: _text(d, "command-text").startswith("{"), "the job JSON shown")
    job = json.loads(_text(browser, "command-text"))
    (tmp_path / "job.json").write_text(json.dumps(job))
    run = subprocess.run([cli, "run", str(tmp_path / "job.json"), "-o", str(tmp_path / "cli"), "--quiet"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    for name in (f["path"] for f in manifest["files"]):
        button = browser.find_element("css selector", f"#results button.download[data-path='{name}']")
        button.click()
        target = browser.downloads / name
        _wait(browser, lambda d: target.exists() and not (browser.downloads / (name + ".crdownload")).exists(),
              f"the download of {name}")
        assert target.read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # The whole folder as one archive: every file the job lists, each as its own download.
    browser.find_element("id", "download-all").click()
    archive = browser.downloads / f"{job_id}.tar"
    _wait(browser, lambda d: archive.exists() and not (browser.downloads / f"{job_id}.tar.crdownload").exists(),
          "the archive's download")
    with tarfile.open(archive) as tar:
        names = tar.getnames()
        assert set(json.loads(body)["files"]) <= set(names)
        for f in manifest["files"]:
            assert tar.extractfile(f["path"]).read() == (browser.downloads / f["path"]).read_bytes()


def test_upload_a_shared_hdr_and_bake_it(server, browser, cli, shared_dir, tmp_path):
    """An environment uploaded from the browser (POST /v1/uploads, under --max-upload, not --max-body), its
    name put in the field, baked; a bad upload's line next to the field; a download byte for byte
    what `brdfbake run` makes of the job the page copies, whose environment is the stored upload."""
    _login(browser, server["url"])
    hdr = shared_dir / "envmaps" / HDR
    bad = tmp_path / "not an image.hdr"
    bad.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 8\n" + b"\x01" * 7)
    browser.find_element("id", "upload-environment").send_keys(str(bad))
    _wait(browser, lambda d: _text(d, "error-environment") != "", "the bad upload's error next to its field")
    message = _text(browser, "error-environment")
    assert "not_an_image.hdr" in message and "\n" not in message, message
    assert str(server["base"]) not in message, message
    _shot(browser, "upload_error")
    browser.find_element("id", "upload-environment").send_keys(str(hdr))
    _wait(browser, lambda d: d.find_element("id", "opt-environment").get_attribute("value").startswith("upload:"),
          "the upload's name in the environment field")
    assert _text(browser, "error-environment") == ""
    name = browser.find_element("id", "opt-environment").get_attribute("value")
    stored = server["base"] / "data" / "uploads" / name[len("upload:"):]
    assert stored.read_bytes() == hdr.read_bytes()
    # "Copy command" names the file as it is on the user's machine, not the server's upload: name
    browser.find_element("id", "copy-command").click()
    command = _text(browser, "command-text")
    assert f"--environment {HDR}" in command and "upload:" not in command.splitlines()[0], command
    assert "# --environment is the file you uploaded as upload:" in command, command
    _set(browser, "target", "generic")
    browser.find_element("id", "preset-draft").click()
    before = _text(browser, "job-id")
    browser.find_element("id", "bake-button").click()
    _wait(browser, lambda d: _text(d, "job-id") not in ("", before)
          and d.execute_script("return document.getElementById('results').dataset.ready === 'true'"),
          "the bake of the upload done and its pictures shown")
    assert _text(browser, "job-state") == "done"
    browser.find_element("id", "copy-result-job").click()
    _wait(browser, lambda d: _text(d, "command-text").startswith("{"), "the job JSON shown")
    job = json.loads(_text(browser, "command-text"))
    assert job["environment"] == str(stored.resolve())
    (tmp_path / "job.json").write_text(json.dumps(job))
    run = subprocess.run([cli, "run", str(tmp_path / "job.json"), "-o", str(tmp_path / "cli"), "--quiet"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    chain = next(t["output"] for t in job["tables"] if t["kind"] == "prefilter")
    target = browser.downloads / chain
    target.unlink(missing_ok=True)  # the Filament test downloaded a chain of this name before
    button = browser.find_element("css selector", f"#results button.download[data-path='{chain}']")
    button.click()
    _wait(browser, lambda d: target.exists() and not (browser.downloads / (chain + ".crdownload")).exists(),
          f"the download of {chain}")
    assert target.read_bytes() == (tmp_path / "cli" / chain).read_bytes(), chain


def test_bake_with_the_material_preview(server, browser):
    """The bake option "preview" (a checkbox generated from GET /v1/bake/options like every option):
    the target's material preview lands with the files and its sheet is drawn, captioned with the
    split-sum's error against the reference."""
    _login(browser, server["url"])
    _set(browser, "environment", "builtin:sun")
    _set(browser, "target", "filament")
    browser.find_element("id", "preset-draft").click()
    if not browser.find_element("id", "more-options").get_attribute("open"):
        browser.find_element("css selector", "#more-options summary").click()
    box = browser.find_element("id", "opt-preview")
    assert box.get_attribute("type") == "checkbox"
    if not box.is_selected():
        box.click()
    before = _text(browser, "job-id")
    browser.find_element("id", "bake-button").click()
    _wait(browser, lambda d: _text(d, "job-id") not in ("", before) and
          d.execute_script("return document.getElementById('results').dataset.ready === 'true'"),
          "the bake with its preview done and its pictures shown")
    assert _text(browser, "job-state") == "done"
    sheet = browser.find_element("css selector", "#results div.file[data-path='preview.png']")
    caption = sheet.find_element("css selector", "p").text
    assert re.search(r"material preview \(filament\): split-sum vs reference, relative RMS [0-9.]+ % median", caption), caption
    pictures = {p["alt"]: p for p in browser.execute_script(PIXELS_JS)}
    p = pictures["contact sheet of preview.png (brdfbake view)"]
    assert p["complete"] and p["width"] > 0 and p["variance"] > 0, p
    for name in ("preview.json", "preview_splitsum.exr", "preview_reference.exr"):
        browser.find_element("css selector", f"#results div.file[data-path='{name}']")
    browser.execute_script("document.querySelector(\"#results div.file[data-path='preview.png']\").scrollIntoView()")
    _shot(browser, "preview")


def test_progress_moves_and_cancel_stops_the_job(server, browser):
    _login(browser, server["url"])
    browser.find_element("id", "preset-production").click()
    _set(browser, "environment", HDR)
    _set(browser, "target", "generic")
    if not browser.find_element("id", "more-options").get_attribute("open"):
        browser.find_element("css selector", "#more-options summary").click()
    _set(browser, "chain_size", "512")  # a chain of several seconds: long enough to be caught running
    before = _text(browser, "job-id")
    browser.find_element("id", "bake-button").click()
    # The new job running, and its bars moving: the DFG table done or the chain under way.
    _wait(browser, lambda d: _text(d, "job-id") not in ("", before) and _text(d, "job-state").startswith("running")
          and d.execute_script("return [...document.querySelectorAll('#job-progress progress')].some(p => p.value > 0)"),
          "the new job running with a bar moving")
    assert "left" in _text(browser, "job-eta") or _text(browser, "job-eta") == ""
    browser.find_element("id", "cancel-button").click()
    _wait(browser, lambda d: _text(d, "job-state") in ("cancelled", "done", "failed"), "the job stopped")
    assert _text(browser, "job-state") == "cancelled"
    assert browser.find_element("id", "results-section").get_attribute("hidden") is not None
