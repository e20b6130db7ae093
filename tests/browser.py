"""A real headless browser for the tests of the pages we write (reports, maps, the live
page): Debian's chromium driven by selenium through Debian's chromium-driver (given by
path, so selenium never looks for a driver or a browser of its own)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

ARGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
        "--disable-background-networking", "--disable-component-update",
        "--disable-default-apps", "--no-first-run")


def chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    pytest.skip("no chromium (make setup installs Debian's chromium)")


class Browser:
    """Headless Chromium over WebDriver (selenium): open pages, run scripts in them."""

    def __init__(self, width: int = 1500, height: int = 1100) -> None:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        driver = shutil.which("chromedriver")
        if driver is None:
            pytest.skip("no chromedriver (make setup installs Debian's chromium-driver)")
        options = webdriver.ChromeOptions()
        options.binary_location = chromium()
        for arg in (*ARGS, f"--window-size={width},{height}"):
            options.add_argument(arg)
        self.driver = webdriver.Chrome(service=Service(driver), options=options)
        self.driver.set_page_load_timeout(120)
        self.driver.set_script_timeout(120)

    def get(self, url: str) -> None:
        """Open `url`; returns once the page has loaded (its load event: images too)."""
        self.driver.get(url)

    def run(self, script: str, *args):
        """The value of a script's `return` (a function body, arguments as `arguments`)."""
        return self.driver.execute_script(script, *args)

    def screenshot(self, path: Path) -> None:
        self.driver.save_screenshot(str(path))

    def links(self) -> list[str]:
        """The absolute URLs of the page's links."""
        return self.run("return Array.from(document.links, a => a.href);")

    def close(self) -> None:
        self.driver.quit()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


IMAGES = ("var imgs = Array.from(document.images);"
          "return [imgs.filter(i => i.complete && i.naturalWidth > 0).length, imgs.length];")


def images_loaded(page: Path, browser: Browser | None = None) -> tuple[int, int]:
    """(loaded, total) images of the page once Chromium has loaded it."""
    if browser is None:
        with Browser() as b:
            return images_loaded(page, b)
    browser.get(Path(page).resolve().as_uri())
    loaded, total = browser.run(IMAGES)
    return int(loaded), int(total)
