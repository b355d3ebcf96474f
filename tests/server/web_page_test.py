#!/usr/bin/python3
"""The web page of `vastray serve` in a real browser: headless Chromium driven by Debian's
chromium-driver through python3-selenium (all installed by scripts/install-deps.sh).

Starts its own `vastray serve` on loopback (port 0) with a temporary data folder and a token
file (or none: --no-token, where the page must never ask), then as a person would: a wrong
token, then the right one; uploads a mesh with the file picker, a two-file OBJ + MTL model
(zipped by the page) and an OBJ by drag and drop; renders 64x64 at 2 spp with AOVs and watches
it to completion; switches through the AOVs and checks each image on screen (a screenshot of
it: the expected size, not uniform); downloads the result; cancels a long job while it runs
(vulkan); sets the lighting and camera controls from the keyboard and checks that the job the
server stored carries them, and that bad values show the server's own 400 message. Prints
figures (page bytes, first contentful paint, main-thread responsiveness while a job streams its
events); they are measurements for docs/SERVICE.md, not assertions.

Exit status 0 when every check passed, 1 otherwise (a missing browser, driver or selenium is
a failure, never a skip: install-deps was supposed to install them).
"""
import argparse
import io
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

TOKEN = "browser-test-token"


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


try:
    from PIL import Image
    from selenium import webdriver
    from selenium.common.exceptions import TimeoutException
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select, WebDriverWait
except ImportError as error:
    fail(f"{error}: run scripts/install-deps.sh (python3-selenium, python3-pil)")


class Server:
    """`vastray serve` on 127.0.0.1, port 0, output in a log file."""

    def __init__(self, vastray, work, backend, token):
        self.data = os.path.join(work, "data")
        self.token = token
        flags = []
        if token:
            flags = ["--auth-token-file", os.path.join(work, "token")]
            with open(flags[1], "w") as f:
                f.write(token + "\n")
        self.log_path = os.path.join(work, "serve.log")
        self.log = open(self.log_path, "w")
        self.process = subprocess.Popen(
            [vastray, "serve", "--data-dir", self.data, "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0",
             "--backend", backend, "--memory-budget", "256MiB", "--shutdown-grace", "0"] + flags,
            stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            text = open(self.log_path).read()
            port = re.search(r"HTTP on 127\.0\.0\.1:(\d+)", text)
            if "ready" in text and port:
                self.url = f"http://127.0.0.1:{port.group(1)}"
                return
            if self.process.poll() is not None:
                break
            time.sleep(0.05)
        self.stop()
        fail(f"vastray serve did not become ready:\n{open(self.log_path).read()}")

    def api(self, path):
        request = urllib.request.Request(self.url + path,
                                         headers={"Authorization": f"Bearer {self.token}"} if self.token else {})
        with urllib.request.urlopen(request, timeout=30) as response:
            return json.load(response)

    def post(self, path, body):
        """POST a JSON body; (HTTP status, the JSON answer), errors included."""
        headers = {"Content-Type": "application/json"}
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        request = urllib.request.Request(self.url + path, data=json.dumps(body).encode(), headers=headers)
        try:
            with urllib.request.urlopen(request, timeout=30) as response:
                return response.status, json.load(response)
        except urllib.error.HTTPError as error:
            return error.code, json.load(error)

    def raw(self, path):
        with urllib.request.urlopen(self.url + path, timeout=30) as response:
            return response.read()

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.log.close()


def browser(chromium, driver, work):
    for path in (chromium, driver):
        if not os.path.exists(path):
            fail(f"{path} is missing: run scripts/install-deps.sh (chromium, chromium-driver)")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    # Root in a container: no sandbox; no GPU; /dev/shm may be tiny.
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--window-size=1280,1800", "--force-device-scale-factor=1",
                 f"--user-data-dir={os.path.join(work, 'chromium-profile')}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "SEVERE"})
    options.add_experimental_option("prefs", {"download.default_directory": os.path.join(work, "downloads"),
                                              "download.prompt_for_download": False})
    # Debian's selenium 4.8 (log_path; later versions call it log_output).
    return webdriver.Chrome(service=Service(driver, log_path=os.path.join(work, "chromedriver.log")), options=options)


class PageTest:
    def __init__(self, server, driver, work, vastray):
        self.server, self.driver, self.work, self.vastray = server, driver, work, vastray
        self.figures = {}

    def wait(self, condition, what, seconds=60):
        try:
            return WebDriverWait(self.driver, seconds, poll_frequency=0.05).until(lambda d: condition())
        except TimeoutException:
            fail(f"timed out after {seconds} s waiting for {what}")

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def element(self, css):
        found = self.driver.find_elements(By.CSS_SELECTOR, css)
        return found[0] if found else None

    def visible_dialog(self):
        return self.js("return document.getElementById('token-dialog').open")

    def enter_token(self, token):
        self.driver.find_element(By.ID, "token-input").send_keys(token)
        self.driver.find_element(By.ID, "token-submit").click()

    def token(self):
        self.driver.get(self.server.url + "/")
        if not self.server.token:
            self.wait(lambda: self.js("return document.body.dataset.ready === 'true'"), "the page to load its data")
            if self.visible_dialog() or self.js("return sessionStorage.getItem('vastray.token')") is not None:
                fail("the page asked for a token that the server does not need")
            return
        self.wait(self.visible_dialog, "the token dialog (the server answers 401)")
        self.figures["first_contentful_paint_ms"] = round(self.wait(lambda: self.js(
            "const e = performance.getEntriesByName('first-contentful-paint');"
            "return e.length ? e[0].startTime : null"), "the first contentful paint entry", 10), 1)
        self.enter_token("wrong-token")
        self.wait(lambda: self.visible_dialog() and "refused" in self.driver.find_element(By.ID, "token-message").text,
                  "the dialog again, saying the token was refused")
        self.enter_token(TOKEN)
        self.wait(lambda: self.js("return document.body.dataset.ready === 'true'"), "the page to load its data")
        if self.visible_dialog():
            fail("the token dialog stays open after the right token")
        if self.js("return sessionStorage.getItem('vastray.token')") != TOKEN:
            fail("the token is not kept in sessionStorage")

    def upload(self, paths, name, drop_text=None, chooser="file-input"):
        if drop_text is None:
            self.driver.find_element(By.ID, chooser).send_keys("\n".join(paths))
        else:
            # Drag and drop: a drop event on the drop zone carrying one file made in the page.
            self.js("""const transfer = new DataTransfer();
                transfer.items.add(new File([arguments[1]], arguments[0]));
                document.getElementById('drop-zone').dispatchEvent(
                    new DragEvent('drop', {dataTransfer: transfer, bubbles: true, cancelable: true}));""",
                    name, drop_text)
        css = f'li.upload[data-name="{name}"]'
        self.wait(lambda: self.element(css) is not None and self.element(css).get_attribute("data-state") in
                  ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED"), f"the upload of {name} to end")
        item = self.element(css)
        if item.get_attribute("data-state") != "JOB_STATE_SUCCEEDED":
            fail(f"upload of {name}: {item.text}")
        rows = [r for r in self.driver.find_elements(By.CSS_SELECTOR, "#scenes tbody tr")
                if r.find_elements(By.TAG_NAME, "td")[0].text == name]
        if not rows:
            fail(f"{name} is not in the scenes table")
        cells = [c.text for c in rows[0].find_elements(By.TAG_NAME, "td")]
        return rows[0].get_attribute("data-scene-id"), cells

    def uploads(self):
        sphere = os.path.join(self.work, "sphere.ply")
        subprocess.run([self.vastray, "generate", "sphere", "--triangles", "2000", "-o", sphere], check=True,
                       stdout=subprocess.DEVNULL)
        scene_id, cells = self.upload([sphere], "sphere.ply")
        stored = self.server.api(f"/v1/scenes/{scene_id}")
        if cells[1] != f"{int(stored['triangles']):,}" or int(stored["chunks"]) < 1 or \
                cells[2] != f"{int(stored['chunks']):,}":
            fail(f"scene row {cells} does not show the scene's triangles and chunks {stored}")
        # Two files of one model: the page zips them (stored) and the server imports the zip.
        with open(os.path.join(self.work, "quad.obj"), "w") as f:
            f.write("mtllib quad.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n")
        with open(os.path.join(self.work, "quad.mtl"), "w") as f:
            f.write("newmtl red\nKd 0.8 0.1 0.1\n")
        quad_id, quad_cells = self.upload([os.path.join(self.work, "quad.obj"), os.path.join(self.work, "quad.mtl")],
                                          "quad.zip")
        if quad_cells[1] != "2" or quad_cells[3] != "zip":
            fail(f"the zipped OBJ + MTL should be 2 triangles in a zip scene: {quad_cells}")
        # A folder (the folder chooser): its files keep their paths in the page's zip; the glTF's
        # buffer lies in a subfolder, and its import fails if that path is lost.
        folder = os.path.join(self.work, "trifolder")
        os.makedirs(os.path.join(folder, "buffers"), exist_ok=True)
        with open(os.path.join(folder, "buffers", "tri.bin"), "wb") as f:
            f.write(struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0))
        with open(os.path.join(folder, "tri.gltf"), "w") as f:
            json.dump({"asset": {"version": "2.0"}, "buffers": [{"uri": "buffers/tri.bin", "byteLength": 36}],
                       "bufferViews": [{"buffer": 0, "byteLength": 36}],
                       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                                      "min": [0, 0, 0], "max": [1, 1, 0]}],
                       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
                       "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}, f)
        _, folder_cells = self.upload([folder], "trifolder.zip", chooser="folder-input")
        if folder_cells[1] != "1" or folder_cells[3] != "zip":
            fail(f"the folder's glTF should be 1 triangle in a zip scene: {folder_cells}")
        _, dropped = self.upload([], "dropped.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        if dropped[1] != "1" or dropped[3] != "obj":
            fail(f"the dropped OBJ should be 1 triangle: {dropped}")
        return scene_id

    def type_into(self, box_id, value):
        box = self.driver.find_element(By.ID, box_id)
        box.clear()
        box.send_keys(str(value))

    def fill(self, scene_id, width, height, spp, aovs=()):
        Select(self.driver.find_element(By.ID, "scene-select")).select_by_value(scene_id)
        for field, value in (("width", width), ("height", height), ("spp", spp)):
            self.type_into(field, value)
        for box in self.driver.find_elements(By.CSS_SELECTOR, "#aovs input"):
            if box.is_selected() != (box.get_attribute("value") in aovs):
                box.click()

    def submit(self, scene_id, width, height, spp, aovs=()):
        self.fill(scene_id, width, height, spp, aovs)
        return self.submit_filled()

    def submit_filled(self):
        """Clicks Render; the id of the job whose card appears."""
        before = {e.get_attribute("data-job-id") for e in self.driver.find_elements(By.CSS_SELECTOR, ".job")}
        self.driver.find_element(By.ID, "submit-render").click()
        self.wait(lambda: len(self.driver.find_elements(By.CSS_SELECTOR, ".job")) > len(before), "the new job's card")
        card = [e for e in self.driver.find_elements(By.CSS_SELECTOR, ".job")
                if e.get_attribute("data-job-id") not in before][0]
        return card.get_attribute("data-job-id")

    def card(self, job_id):
        return self.driver.find_element(By.ID, f"job-{job_id}")

    def render_and_watch(self, scene_id, aovs):
        job_id = self.submit(scene_id, 64, 64, 2, aovs)
        final = ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED", "JOB_STATE_CANCELLED")
        self.wait(lambda: self.card(job_id).get_attribute("data-state") in final, "the render to end", 120)
        card = self.card(job_id)
        if card.get_attribute("data-state") != "JOB_STATE_SUCCEEDED":
            fail(f"the render did not succeed: {card.text}")
        # data-state is the API's name; a person reads it without the enum's prefix.
        shown = card.find_element(By.CLASS_NAME, "state").text
        if shown != "SUCCEEDED":
            fail(f"the card shows the state as {shown!r}, not 'SUCCEEDED'")
        if self.js("return arguments[0].querySelector('progress').value", card) != 100:
            fail("the progress bar is not full at SUCCEEDED")
        self.wait(lambda: "rays/s" in card.text and "device" in card.text, "rays/s and device memory on the card")
        text = card.text
        if not re.search(r"device [\d.]+ \w+ of 256\.0 MiB", text) or "chunk loads" not in text:
            fail(f"the card lacks device memory against the 256 MiB budget or chunk loads: {text}")
        return job_id

    def check_image(self, aov):
        image = self.driver.find_element(By.ID, "result-image")
        self.js("arguments[0].scrollIntoView({block: 'center'})", image)
        natural = self.js("const i = arguments[0]; return [i.naturalWidth, i.naturalHeight]", image)
        if natural != [64, 64]:
            fail(f"{aov}: the image is {natural}, not 64x64")
        shot = Image.open(io.BytesIO(image.screenshot_as_png)).convert("RGB")
        shot.save(os.path.join(self.work, f"screenshot-{aov}.png"))
        if shot.size[0] < 64 or abs(shot.size[0] - shot.size[1]) > 1:
            fail(f"{aov}: the image shows at {shot.size}, expected a square of at least 64 pixels")
        colours = shot.getcolors(maxcolors=1 << 20)
        if colours is None or len(colours) < 2:
            fail(f"{aov}: the image on screen is uniform")
        return len(colours)

    def view_aovs(self, job_id, aovs):
        self.card(job_id).find_element(By.CSS_SELECTOR, "button.view").click()
        image = lambda: self.driver.find_element(By.ID, "result-image")  # noqa: E731
        self.wait(lambda: image().get_attribute("data-aov") == "beauty", "the beauty in the viewer")
        buttons = [b.get_attribute("data-aov") for b in self.driver.find_elements(By.CSS_SELECTOR, "#aov-switcher button")]
        if buttons != ["beauty", *aovs]:
            fail(f"AOV switcher shows {buttons}")
        colours = {"beauty": self.check_image("beauty")}
        seen = {}
        for aov in buttons[1:]:
            self.driver.find_element(By.CSS_SELECTOR, f'#aov-switcher button[data-aov="{aov}"]').click()
            self.wait(lambda: image().get_attribute("data-aov") == aov, f"the {aov} image", 30)
            colours[aov] = self.check_image(aov)
            seen[aov] = self.js("return arguments[0].src", image())
        if len(set(seen.values())) != len(seen):
            fail("switching AOVs did not change the image")
        if self.driver.find_element(By.ID, "viewer-message").text:
            fail(f"viewer error: {self.driver.find_element(By.ID, 'viewer-message').text}")
        print("distinct colours on screen per AOV:", colours)

    def download(self, job_id):
        self.driver.find_element(By.ID, "download").click()
        path = os.path.join(self.work, "downloads", f"{job_id}.exr")
        expected = int(self.server.api(f"/v1/jobs/{job_id}")["result_bytes"])
        self.wait(lambda: os.path.exists(path) and os.path.getsize(path) == expected,
                  f"the download of {job_id}.exr ({expected} bytes)", 30)
        with open(path, "rb") as f:
            if f.read(4) != b"\x76\x2f\x31\x01":
                fail("the downloaded file is not an EXR")

    def cancel_long_job(self, scene_id):
        job_id = self.submit(scene_id, 512, 512, 4096)
        self.wait(lambda: self.card(job_id).get_attribute("data-state") == "JOB_STATE_RUNNING", "the long job to run", 60)
        self.card(job_id).find_element(By.CSS_SELECTOR, "button.cancel").click()
        self.wait(lambda: self.card(job_id).get_attribute("data-state") == "JOB_STATE_CANCELLED", "CANCELLED on the card", 30)
        job = self.server.api(f"/v1/jobs/{job_id}")
        if job["state"] != "JOB_STATE_CANCELLED" or "cancelled from the web page" not in job["error"]:
            fail(f"the server does not say CANCELLED by the page: {job['state']} {job['error']}")

    def responsiveness(self, scene_id):
        """While a job streams every progress event the server publishes (one per percent and per
        last pass, chunk loads at most every 100 ms: docs/SERVICE.md, Progress), from submit to
        SUCCEEDED: the gaps between animation frames and the main thread's long tasks (> 50 ms)."""
        self.js("""
            window.probe = {gaps: [], longTasks: [], last: performance.now(), events0: vastrayPage.events};
            new PerformanceObserver((l) => l.getEntries().forEach((e) => probe.longTasks.push(e.duration)))
                .observe({type: 'longtask'});
            const tick = (t) => { probe.gaps.push(t - probe.last); probe.last = t; probe.raf = requestAnimationFrame(tick); };
            probe.raf = requestAnimationFrame(tick);""")
        start = time.monotonic()
        job_id = self.submit(scene_id, 128, 128, 128)
        self.wait(lambda: self.card(job_id).get_attribute("data-state") == "JOB_STATE_SUCCEEDED", "the streamed job to end", 120)
        seconds = time.monotonic() - start
        probe = self.js("""cancelAnimationFrame(probe.raf);
            return {gaps: probe.gaps, longTasks: probe.longTasks, events: vastrayPage.events - probe.events0}""")
        gaps = sorted(probe["gaps"][1:])
        self.figures.update({
            "streaming_job": "128x128, 128 spp",
            "streaming_seconds": round(seconds, 2),
            "events_received": probe["events"],
            "animation_frames": len(gaps),
            "frame_gap_ms_median": round(gaps[len(gaps) // 2], 1) if gaps else None,
            "frame_gap_ms_max": round(gaps[-1], 1) if gaps else None,
            "long_tasks": len(probe["longTasks"]),
            "long_task_ms_total": round(sum(probe["longTasks"]), 1),
        })

    def choose(self, select_id, value):
        """Chooses an option of a select from the keyboard: Home, then Down to it."""
        box = self.driver.find_element(By.ID, select_id)
        values = [o.get_attribute("value") for o in box.find_elements(By.TAG_NAME, "option")]
        box.send_keys(Keys.HOME + Keys.ARROW_DOWN * values.index(value))
        self.wait(lambda: box.get_attribute("value") == value, f"{select_id} to be {value!r} by keyboard", 5)

    def tab_from(self, element_id):
        """The id of the control Tab moves to from `element_id`."""
        self.driver.find_element(By.ID, element_id).send_keys(Keys.TAB)
        return self.js("return document.activeElement.id")

    def tab_twice_from(self, element_id):
        """The id of the control two Tabs move to from `element_id` (past a file input, which takes
        no keys from WebDriver: its send_keys chooses a file)."""
        self.driver.find_element(By.ID, element_id).send_keys(Keys.TAB)
        ActionChains(self.driver).send_keys(Keys.TAB).perform()
        return self.js("return document.activeElement.id")

    def fill_vector(self, prefix, values):
        for axis, value in zip("xyz", values):
            self.type_into(f"{prefix}-{axis}", value)

    def stored_request(self, job_id, expected, absent=()):
        request = self.server.api(f"/v1/jobs/{job_id}")["request"]
        got = {key: request.get(key) for key in expected}
        if got != expected or any(key in request for key in absent):
            fail(f"the job the form submitted carries {request}, expected {expected} and no {list(absent)}")

    def lit_job(self, scene_id):
        """Finest texture levels, up axis z, a sun of its own, the scene's lights off and an eye/target
        camera, all set from the keyboard; Tab reaches only the boxes of the chosen sun and camera."""
        self.fill(scene_id, 64, 64, 2)
        self.choose("texture-lod", "finest")
        self.driver.find_element(By.CSS_SELECTOR, "#light-camera summary").send_keys(Keys.ENTER)
        self.wait(lambda: self.js("return document.getElementById('light-camera').open"),
                  "Enter on 'lighting and camera' to open it", 5)
        if self.tab_from("sun-mode") != "scene-lights":
            fail("Tab from the default sun does not skip the custom sun's boxes")
        self.choose("up-axis", "z")
        self.choose("sun-mode", "custom")
        if self.tab_from("sun-mode") != "sun-x":
            fail("Tab from 'this sun' does not reach the sun's direction")
        self.fill_vector("sun", (1, 2, 0.5))
        self.type_into("sun-intensity", 7.5)
        lights = self.driver.find_element(By.ID, "scene-lights")
        lights.send_keys(Keys.SPACE)
        if lights.is_selected():
            fail("Space did not turn the scene's lights off")
        self.choose("camera-mode", "eye")
        if self.tab_from("camera-mode") != "eye-x":
            fail("Tab from 'eye and target' does not skip the scene camera's box to reach the eye")
        self.fill_vector("eye", (0, -3, 1))
        self.fill_vector("target", (0, 0, 0.25))
        self.type_into("fov", 50)
        job_id = self.submit_filled()
        # The camera's up left empty: the server fills in the up axis.
        self.stored_request(job_id, {
            "up_axis": "z", "sun": {"direction": [1, 2, 0.5], "intensity": 7.5}, "no_lights": True,
            "camera": {"eye": [0, -3, 1], "target": [0, 0, 0.25], "up": [0, 0, 1], "fov_y_degrees": 50},
            "scene_camera": "", "texture_lod": "finest"})
        final = ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED", "JOB_STATE_CANCELLED")
        self.wait(lambda: self.card(job_id).get_attribute("data-state") in final, "the lit job to end", 120)
        if self.card(job_id).get_attribute("data-state") != "JOB_STATE_SUCCEEDED":
            fail(f"the lit job did not succeed: {self.card(job_id).text}")

    def scene_camera_job(self):
        """No sun and a scene camera by index: stored as the API's sun of intensity 0 and
        scene_camera; the sphere has no camera, so the job fails and its card shows why."""
        self.choose("sun-mode", "none")
        self.choose("camera-mode", "scene")
        self.type_into("scene-camera", "1")
        job_id = self.submit_filled()
        self.stored_request(job_id, {"up_axis": "z", "sun": {"direction": [0, 0, 1], "intensity": 0},
                                     "scene_camera": "1", "no_lights": True}, absent=("camera",))
        self.wait(lambda: self.card(job_id).get_attribute("data-state") == "JOB_STATE_FAILED", "the job to fail", 60)
        error = self.server.api(f"/v1/jobs/{job_id}")["error"]
        self.wait(lambda: error in self.card(job_id).text, "the job's error on its card", 10)
        if "defines no cameras" not in error:
            fail(f"the scene camera job failed for another reason: {error}")

    def refused(self, scene_id, request, field):
        """Submits the form as it stands; the page must show the server's own answer to `request`
        (what the form sends, posted directly), which names `field`, and add no job."""
        status, answer = self.server.post("/v1/jobs", {"scene_id": scene_id, "width": 64, "height": 64,
                                                       "spp": 2, **request})
        if status != 400 or not answer["error"]["message"].startswith(field + ":"):
            fail(f"the API should refuse {request} naming {field}: {status} {answer}")
        expected = f"{status} {answer['error']['code']}: {answer['error']['message']}"
        cards = len(self.driver.find_elements(By.CSS_SELECTOR, ".job"))
        self.driver.find_element(By.ID, "submit-render").click()
        message = lambda: self.driver.find_element(By.ID, "render-message").text  # noqa: E731
        self.wait(lambda: message() == expected, f"the server's error {expected!r} (the page shows {message()!r})", 10)
        if len(self.driver.find_elements(By.CSS_SELECTOR, ".job")) != cards:
            fail(f"a refused request ({request}) added a job card")

    def lighting_and_camera(self, scene_id):
        self.lit_job(scene_id)
        self.scene_camera_job()
        lit = {"up_axis": "z", "no_lights": True}
        self.choose("sun-mode", "custom")
        self.choose("camera-mode", "default")
        self.fill_vector("sun", (0, 0, 0))
        self.refused(scene_id, {**lit, "sun": {"direction": [0, 0, 0], "intensity": 7.5}}, "sun.direction")
        self.fill_vector("sun", (1, 2, 0.5))
        self.type_into("sun-intensity", 2000000)
        self.refused(scene_id, {**lit, "sun": {"direction": [1, 2, 0.5], "intensity": 2000000}}, "sun.intensity")
        self.type_into("sun-intensity", 7.5)
        # The 65-byte name reaches the server whole (the box does not cut it).
        self.choose("camera-mode", "scene")
        self.type_into("scene-camera", "c" * 65)
        self.refused(scene_id, {**lit, "sun": {"direction": [1, 2, 0.5], "intensity": 7.5},
                                "scene_camera": "c" * 65}, "scene_camera")
        # An empty box is left out, and the server says what is missing.
        self.choose("camera-mode", "eye")
        self.type_into("eye-z", "")
        self.refused(scene_id, {**lit, "sun": {"direction": [1, 2, 0.5], "intensity": 7.5},
                                "camera": {"eye": [0, -3], "target": [0, 0, 0.25], "fov_y_degrees": 50}},
                     "camera.eye")
        self.listed_camera_job(scene_id)

    def listed_camera_job(self, sphere_id):
        """A glTF with cameras "Near" and "Far" (dropped on the page): choosing it fills the camera
        list from Scene.cameras; picking "1: Far" by keyboard writes its name into the box, and the
        job renders with scene_camera "Far"."""
        gltf = json.dumps({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,"
                         "AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAAAAAAAAgD8AAAAA"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                           "min": [-1, -1, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "cameras": [{"name": "Near", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}},
                        {"name": "Far", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
            "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}, {"camera": 1, "translation": [0, 0, 6]}],
            "scenes": [{"nodes": [0, 1, 2]}]})
        scene_id, _ = self.upload([], "cameras.gltf", gltf)
        self.fill(scene_id, 32, 32, 2)
        self.choose("sun-mode", "default")
        self.choose("camera-mode", "scene")
        if self.tab_from("camera-mode") != "scene-camera-list":
            fail("Tab from 'a scene camera' does not reach the list of the scene's cameras")
        options = lambda: [o.text for o in self.driver.find_elements(By.CSS_SELECTOR, "#scene-camera-list option")]  # noqa: E731
        self.wait(lambda: options()[:2] == ["0: Near", "1: Far"], f"the scene's cameras in the list ({options()})", 5)
        self.type_into("scene-camera", "")
        self.choose("scene-camera-list", "1")
        box = self.driver.find_element(By.ID, "scene-camera")
        self.wait(lambda: box.get_attribute("value") == "Far", "picking '1: Far' to write Far into the box", 5)
        job_id = self.submit_filled()
        self.stored_request(job_id, {"scene_id": scene_id, "scene_camera": "Far"}, absent=("camera",))
        final = ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED", "JOB_STATE_CANCELLED")
        self.wait(lambda: self.card(job_id).get_attribute("data-state") in final, "the listed-camera job to end", 120)
        if self.card(job_id).get_attribute("data-state") != "JOB_STATE_SUCCEEDED":
            fail(f"the job with a listed camera did not succeed: {self.card(job_id).text}")
        # The sphere defines no camera: choosing it leaves only the box's option.
        self.fill(sphere_id, 32, 32, 2)
        self.wait(lambda: options() == ["none defined (the box below)"],
                  f"a scene without cameras to list none ({options()})", 5)

    def environment_job(self, scene_id):
        """An environment map uploaded through the page's picker (a garbage one first: the page shows
        the server's refusal naming the file) is chosen in the environment select; its scale and
        rotation boxes, skipped by Tab while no map is chosen, and the uv AOV box are set from the
        keyboard; the job is stored with exactly those fields and SUCCEEDS. A scale out of range
        shows the API's own 400."""
        garbage = os.path.join(self.work, "garbage.hdr")
        with open(garbage, "wb") as f:
            f.write(b"#?RADIANCE\nnot a picture")
        studio = os.path.join(self.work, "studio.hdr")
        with open(studio, "wb") as f:  # 8x4 flat RGBE texels of 1.0
            f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n" + b"\x80\x80\x80\x81" * 32)
        message = lambda: self.driver.find_element(By.ID, "environment-message").text  # noqa: E731
        self.driver.find_element(By.ID, "environment-file").send_keys(garbage)
        self.wait(lambda: message().startswith("400 INVALID_ARGUMENT: data: garbage.hdr"),
                  f"the refusal of garbage.hdr naming it (the page shows {message()!r})", 20)
        self.driver.find_element(By.ID, "environment-file").send_keys(studio)
        self.wait(lambda: message() == "studio.hdr stored", f"studio.hdr to be stored ({message()!r})", 20)
        stored = [e for e in self.server.api("/v1/environments")["environments"] if e["name"] == "studio.hdr"]
        if len(stored) != 1 or (stored[0]["width"], stored[0]["height"]) != (8, 4):
            fail(f"the uploaded map is not listed as an 8x4 studio.hdr: {stored}")
        environment_id = stored[0]["id"]
        self.fill(scene_id, 32, 32, 2)
        self.choose("sun-mode", "default")
        self.choose("camera-mode", "default")
        self.choose("environment-select", "")
        if self.tab_from("environment-select") != "environment-file":
            fail("Tab from the environment select does not reach the upload picker")
        if self.tab_twice_from("environment-select") == "environment-scale":
            fail("Tab reaches the environment's scale while no map is chosen")
        self.choose("environment-select", environment_id)
        if self.tab_twice_from("environment-select") != "environment-scale":
            fail("Tab past the environment picker does not reach the chosen map's scale")
        self.type_into("environment-scale", 0.5)
        self.type_into("environment-rotation", 45)
        uv = self.driver.find_element(By.CSS_SELECTOR, "#aovs input[value='uv']")
        uv.send_keys(Keys.SPACE)
        if not uv.is_selected():
            fail("Space did not tick the uv AOV box")
        job_id = self.submit_filled()
        self.stored_request(job_id, {
            "scene_id": scene_id, "aovs": ["uv"], "output_format": "exr",
            "environment": {"id": environment_id, "scale": 0.5, "rotation_degrees": 45}}, absent=("sun", "camera"))
        final = ("JOB_STATE_SUCCEEDED", "JOB_STATE_FAILED", "JOB_STATE_CANCELLED")
        self.wait(lambda: self.card(job_id).get_attribute("data-state") in final, "the environment job to end", 120)
        if self.card(job_id).get_attribute("data-state") != "JOB_STATE_SUCCEEDED":
            fail(f"the environment job did not succeed: {self.card(job_id).text}")
        self.type_into("environment-scale", -1)
        up_axis = self.driver.find_element(By.ID, "up-axis").get_attribute("value")
        self.refused(scene_id, {"up_axis": up_axis, "no_lights": not self.driver.find_element(By.ID, "scene-lights").is_selected(),
                                "aovs": ["uv"], "environment": {"id": environment_id, "scale": -1, "rotation_degrees": 45}},
                     "environment.scale")
        self.choose("environment-select", "")

    def page_bytes(self):
        html = self.server.raw("/")
        scripts = re.findall(rb'src="([^"]+)"', html) + re.findall(rb'href="([^"]+\.css)"', html)
        sizes = {"index.html": len(html)}
        for path in scripts:
            sizes[path.decode()] = len(self.server.raw("/" + path.decode()))
        self.figures["page_bytes"] = sizes
        self.figures["page_bytes_total"] = sum(sizes.values())

    def run(self, backend):
        self.page_bytes()
        self.token()
        scene_id = self.uploads()
        # chunkid and cost exist only in the streaming (vulkan) renderer.
        aovs = ["depth", "normal", "albedo"] + (["chunkid", "cost"] if backend == "vulkan" else [])
        job_id = self.render_and_watch(scene_id, aovs)
        self.stored_request(job_id, {"texture_lod": "cone"})  # the select's first option
        self.view_aovs(job_id, aovs)
        self.download(job_id)
        self.driver.save_screenshot(os.path.join(self.work, "page.png"))
        # Embree cannot stop inside a render (docs/SERVICE.md): its cancelled job would burn both
        # cores to its end, so the cancel and the figures are taken on vulkan only.
        if backend == "vulkan":
            self.cancel_long_job(scene_id)
            self.responsiveness(scene_id)
        self.lighting_and_camera(scene_id)
        self.environment_job(scene_id)
        # The 401s that made the page ask for the token and the 400s of the refused jobs are
        # expected; nothing else may be logged (a CSP violation, a failed request, an exception).
        expected = ("status of 401 (Unauthorized)", "/v1/jobs - Failed to load resource: the server responded "
                    "with a status of 400 (Bad Request)", "/v1/environments?name=garbage.hdr - Failed to load "
                    "resource: the server responded with a status of 400 (Bad Request)")
        errors = [e for e in self.driver.get_log("browser")
                  if e["level"] == "SEVERE" and not any(text in e["message"] for text in expected)]
        if errors:
            fail(f"errors in the browser console: {errors}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vastray", required=True)
    parser.add_argument("--work", required=True, help="folder for the data, logs and screenshots (emptied)")
    parser.add_argument("--backend", default="vulkan", choices=["vulkan", "embree"])
    parser.add_argument("--no-token", action="store_true", help="serve without --auth-token-file")
    parser.add_argument("--chromium", default="/usr/bin/chromium")
    parser.add_argument("--chromedriver", default="/usr/bin/chromedriver")
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    began = time.monotonic()
    server = Server(args.vastray, args.work, args.backend, None if args.no_token else TOKEN)
    driver = None
    try:
        driver = browser(args.chromium, args.chromedriver, args.work)
        test = PageTest(server, driver, args.work, args.vastray)
        try:
            test.run(args.backend)
        except SystemExit:
            driver.save_screenshot(os.path.join(args.work, "failure.png"))
            print(f"page at failure: {os.path.join(args.work, 'failure.png')}; server log: {server.log_path}")
            raise
        version = driver.capabilities.get("browserVersion", "?")
        print(f"FIGURES backend={args.backend} chromium={version} "
              f"{json.dumps(test.figures, sort_keys=True)}")
    finally:
        if driver:
            driver.quit()
        server.stop()
    print(f"PASS in {time.monotonic() - began:.1f} s")


if __name__ == "__main__":
    main()
