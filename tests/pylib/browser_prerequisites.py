"""The browser tests' prerequisites: Playwright's Python module and Debian's chromium.

A test without them is skipped (exit 77, ctest's SKIP_RETURN_CODE) naming what is missing and
what installs it, rather than failing on an import.
"""
import os
import sys

CHROMIUM = "/usr/bin/chromium"


def skip(why):
    print(f"SKIP: {why}")
    sys.exit(77)


def require_browser():
    """Returns Playwright's sync_playwright, or skips the test when it or chromium is missing."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        skip("the playwright Python module is not installed (scripts/setup.sh installs it)")
    if not os.access(CHROMIUM, os.X_OK):
        skip(f"{CHROMIUM} is not installed (Debian package chromium; scripts/setup.sh installs it)")
    return sync_playwright
