#!/usr/bin/env python3
"""ctest browser.report_html: the demo's report.html and a sweep's report.html in headless Chromium.

Checks what a person opening the pages would notice: every image loads (no broken image), the
console shows no error, no script throws, and the view wipe slider works. A page with a broken
image and a console error is checked first, so the check itself is shown to catch both.
Usage: report_html_test.py AL_REFINE_BIN [--screenshot PNG] [--keep DIR]
Exit 77 (skipped) when Chromium is missing, unless AL_REQUIRE_TEST_DATA=1 (CI), where it fails.
"""
import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import cdp_page_check as cdp  # noqa: E402

# Moves the first view's slider to 20 % and returns the wiped image's clip-path.
WIPE_JS = """(function () {
  var card = document.querySelector('section.view');
  var wipe = card.querySelector('input.wipe');
  wipe.value = 20;
  wipe.dispatchEvent(new Event('input', {bubbles: true}));
  return card.querySelector('.compare img.top').style.clipPath;
})()"""


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args, **kw):
    proc = subprocess.run(args, capture_output=True, text=True, timeout=900, **kw)
    if proc.returncode != 0:
        fail(f"{' '.join(map(str, args))} exited {proc.returncode}: {proc.stderr[-2000:]}")
    return proc.stdout


def self_test(chromium, work):
    page = work / "broken.html"
    page.write_text('<!DOCTYPE html><html><body><img src="missing.png"><script>console.error("seen")</script>'
                    "</body></html>")
    r = cdp.check_page(chromium, page)
    if len(r["broken"]) != 1 or not any("seen" in e for e in r["errors"]) or \
            not any("missing.png" in e for e in r["errors"]):
        fail(f"the checker missed a broken image or a console error: {r}")
    print("self-test: a broken image and a console error are caught")


def check(chromium, page, min_images, screenshot=None, script=None, height=900):
    r = cdp.check_page(chromium, page, screenshot=screenshot, script=script, height=height)
    if r["broken"]:
        fail(f"{page}: {len(r['broken'])} broken image(s), e.g. {r['broken'][:3]}")
    if r["errors"]:
        fail(f"{page}: console errors: {r['errors'][:5]}")
    if len(r["images"]) < min_images:
        fail(f"{page}: {len(r['images'])} images, expected at least {min_images}")
    print(f"{page}: {len(r['images'])} images loaded, no console error")
    return r


def demo_report(cli, chromium, work, screenshot):
    out = work / "demo"
    stdout = run([cli, "demo", "--out", out, "--gaussians", "30000", "--views", "6", "--quiet"])
    first = stdout.splitlines()[0]
    page = out / "eval" / "report.html"
    if first != f"report: {os.path.abspath(page)}":
        fail(f"the demo's first line should name report.html, got: {first!r}")
    # before + 3 renders + 3 residual overlays + 2 added overlays + 3 depth changes, twice (strip + wipe).
    r = check(chromium, page, min_images=6, screenshot=screenshot, script=WIPE_JS, height=1500)
    if r["script"] != "inset(0px 80% 0px 0px)":
        fail(f"the wipe slider did not move the picture: clip-path {r['script']!r}")
    print("demo report.html: wipe slider works")
    # The demo's scene has semantic features: the page names the feature metrics and shows the
    # feature segmentation pictures (loaded above with every other image).
    html = page.read_text(encoding="utf-8")
    for needle in ("<h2>Feature metrics</h2>", "IoU_drop_feat ↑", "residual_feat ↓", "_featseg.png"):
        if needle not in html:
            fail(f"{page}: no {needle!r} although the demo scores the feature metrics")
    print("demo report.html: feature metrics and feature segmentation shown")
    return out


def sweep_report(cli, chromium, demo, work):
    scene = demo / "scene"
    out = work / "sweep"
    run([cli, "sweep", "--scene", scene / "scene.ply", "--removed", scene / "removed_fgs.npy", "--method", "fgs",
         "--labels", scene / "labels.npy", "--grid", "k=6,10;delta=0.8,1.0;solver=bk", "--quiet", "--out", out])
    r = check(chromium, out / "report.html", min_images=2)
    if not any(i["src"] == "pareto.png" for i in r["images"]):
        fail("the sweep page does not show pareto.png")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("cli")
    parser.add_argument("--screenshot")
    parser.add_argument("--keep")
    args = parser.parse_args()
    chromium = cdp.find_chromium()
    if not chromium:
        if os.environ.get("AL_REQUIRE_TEST_DATA") == "1":
            fail("chromium is not installed (scripts/setup installs it)")
        print("SKIP: chromium is not installed")
        sys.exit(77)
    with tempfile.TemporaryDirectory(prefix="al_browser_") as tmp:
        work = Path(args.keep) if args.keep else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        self_test(chromium, work)
        demo = demo_report(args.cli, chromium, work, args.screenshot)
        sweep_report(args.cli, chromium, demo, work)
    print("1 passed, 0 failed")


if __name__ == "__main__":
    main()
