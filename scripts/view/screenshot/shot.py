"""Screenshots a page with Debian's Chromium driven by Playwright (no browser download).

    shot.py URL OUT.png WAIT_SECONDS
"""
import sys
import time

from playwright.sync_api import sync_playwright

url, out, wait = sys.argv[1], sys.argv[2], float(sys.argv[3])
with sync_playwright() as p:
    browser = p.chromium.launch(executable_path="/usr/bin/chromium",
                                args=["--no-sandbox", "--enable-unsafe-swiftshader", "--use-angle=swiftshader"])
    page = browser.new_page(viewport={"width": 1600, "height": 1000})
    page.on("pageerror", lambda e: print("page error:", e, file=sys.stderr))
    page.goto(url, wait_until="load")
    time.sleep(wait)
    page.screenshot(path=out)
    browser.close()
print("wrote", out)
