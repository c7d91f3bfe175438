"""The page of `codegen sim` in a real browser: headless Chromium (Debian's, with its ChromeDriver) driven by
Selenium. Run by codegen/tests/sim.rs against a server it started on the cell:

    python sim_browser.py URL SCREENSHOT

Loads the page, steps a controllable event and sees a supervisor's state change and a disabled event's
reason, reverts, runs 1 000 events and sees coverage on the table and the graphs, then saves a
screenshot. Every wait is bounded (the whole run takes a few seconds); a failed check exits 1 with why.
"""

import sys
from urllib.parse import unquote

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

# Far beyond what a page of this size takes on a loaded machine; only a broken page reaches it.
WAIT_S = 60
# The colour of a supervisor's transition the trace took (codegen/src/sim/draw.rs: green).
TAKEN = "#008000"


def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--force-device-scale-factor=1",
        "--window-size=1600,1500",
    ]:
        options.add_argument(flag)
    return webdriver.Chrome(options=options, service=Service(executable_path="/usr/bin/chromedriver"))


def texts(driver, css):
    return [e.text for e in driver.find_elements(By.CSS_SELECTOR, css)]


def currents(driver):
    """Each supervisor's current state, as its graph's heading shows it."""
    return {
        g.get_attribute("data-automaton"): g.find_element(By.CSS_SELECTOR, ".current").text
        for g in driver.find_elements(By.CSS_SELECTOR, ".graph.supervisor")
    }


def trace_length(driver):
    return len(driver.find_elements(By.CSS_SELECTOR, "#trace li")) - 1


def main():
    url, screenshot = sys.argv[1], sys.argv[2]
    driver = browser()
    try:
        wait = WebDriverWait(driver, WAIT_S)
        driver.get(url)
        wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#enabled button"))
        before = currents(driver)
        assert before, "no supervisor drawn"
        assert all(img.get_attribute("src").startswith("data:image/svg+xml")
                   for img in driver.find_elements(By.CSS_SELECTOR, ".graph img")), "a graph is not drawn"
        # Step the first controllable event every supervisor enables.
        button = driver.find_element(By.CSS_SELECTOR, "#enabled button")
        event = button.text
        button.click()
        wait.until(lambda d: trace_length(d) == 1)
        after = currents(driver)
        changed = [s for s in before if before[s] != after.get(s)]
        assert changed, f"{event}: no supervisor changed state ({before} → {after})"
        reasons = texts(driver, "#disabled .by")
        assert any(r.strip() for r in reasons), f"after {event}: no disabled event with its supervisors"
        print(f"stepped {event}: {', '.join(f'{s} {before[s]} → {after[s]}' for s in changed)}; "
              f"disabled: {'; '.join(texts(driver, '#disabled li'))}")
        # Revert by clicking the trace's first line (the initial state).
        driver.find_element(By.CSS_SELECTOR, "#trace li[data-step='0']").click()
        wait.until(lambda d: trace_length(d) == 0)
        assert currents(driver) == before, "revert did not restore the supervisors' states"
        # Run 1 000 events.
        count = driver.find_element(By.ID, "count")
        count.clear()
        count.send_keys("1000")
        driver.find_element(By.ID, "run").click()
        wait.until(lambda d: trace_length(d) == 1000)
        rows = driver.find_elements(By.CSS_SELECTOR, "#coverage tr")
        taken = [int(r.find_elements(By.TAG_NAME, "td")[1].text.split("/")[0]) for r in rows]
        assert rows and all(t > 0 for t in taken), f"coverage after the run: {texts(driver, '#coverage tr')}"
        green = [g.get_attribute("data-automaton") for g in driver.find_elements(By.CSS_SELECTOR, ".graph.supervisor")
                 if TAKEN in unquote(g.find_element(By.TAG_NAME, "img").get_attribute("src"))]
        assert green, "no supervisor graph shows a taken transition"
        print("coverage after 1000 events: " + "; ".join(texts(driver, "#coverage tr")))
        driver.save_screenshot(screenshot)
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
