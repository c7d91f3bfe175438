"""The page of `codegen sim` in a real browser: headless Chromium (Debian's, with its ChromeDriver) driven by
Selenium. Run by codegen/tests/sim.rs against servers it started, one browser for them all:

    python sim_browser.py SCREENSHOT cell=URL [factory=URL] [net=URL] [agv=URL]

- cell: steps a controllable event and sees a supervisor's state change and a disabled event's reason,
  reverts, runs 1 000 events and sees coverage on the table and the graphs, then saves the screenshot;
- factory, agv: the same step, revert and run (fewer events), coverage on the graphs, and `check`'s
  findings outlined red on them; for the AGV also a large supervisor drawn around its current state and
  expanded one level by its button;
- net (a Petri-net sequence): steps an event the sequence requests and sees the marking change.

The AGV comes last: its server may still be synthesising, and the script waits for it to listen.

Every wait is bounded; a failed check exits 1 with why. Each project's seconds are printed.
"""

import socket
import sys
import time
from urllib.parse import unquote, urlsplit

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

# Far beyond what a page of this size takes on a loaded machine; only a broken page reaches it.
WAIT_S = 60
# A server that synthesises first (the AGV: about half a minute on a loaded machine) is given this long.
STARTING_S = 600
# The colour of a supervisor's transition the trace took (codegen/src/sim/draw.rs: green).
TAKEN = "#008000"
# The outline of a state where a `check` finding occurs (draw.rs: red).
FLAGGED = "#ff0000"


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


def graph_svgs(driver, css):
    """Each graph's name and its SVG, for the graphs `css` selects."""
    return {g.get_attribute("data-automaton"): unquote(g.find_element(By.TAG_NAME, "img").get_attribute("src"))
            for g in driver.find_elements(By.CSS_SELECTOR, css)}


def load(driver, wait, url):
    driver.get(url)
    wait.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#enabled button"))
    assert all(img.get_attribute("src").startswith("data:image/svg+xml")
               for img in driver.find_elements(By.CSS_SELECTOR, ".graph img")), "a graph is not drawn"


def step_and_revert(driver, wait, name, stepped=None):
    """Steps the first controllable event every supervisor enables, sees a supervisor's state change,
    calls `stepped(event)` (if given) on the stepped page, and reverts to the initial state by clicking
    the trace's first line; returns the event."""
    before = currents(driver)
    assert before, f"{name}: no supervisor drawn"
    button = driver.find_element(By.CSS_SELECTOR, "#enabled button")
    event = button.text
    button.click()
    wait.until(lambda d: trace_length(d) == 1)
    after = currents(driver)
    changed = [s for s in before if before[s] != after.get(s)]
    assert changed, f"{name}: {event}: no supervisor changed state ({before} → {after})"
    print(f"{name}: stepped {event}: {', '.join(f'{s} {before[s]} → {after[s]}' for s in changed)}")
    if stepped is not None:
        stepped(event)
    driver.find_element(By.CSS_SELECTOR, "#trace li[data-step='0']").click()
    wait.until(lambda d: trace_length(d) == 0)
    assert currents(driver) == before, f"{name}: revert did not restore the supervisors' states"
    return event


def run(driver, wait, name, events):
    """Runs `events` events and sees coverage in the table and green on a supervisor's graph."""
    count = driver.find_element(By.ID, "count")
    count.clear()
    count.send_keys(str(events))
    driver.find_element(By.ID, "run").click()
    wait.until(lambda d: trace_length(d) == events)
    rows = driver.find_elements(By.CSS_SELECTOR, "#coverage tr")
    taken = [int(r.find_elements(By.TAG_NAME, "td")[1].text.split("/")[0]) for r in rows]
    assert rows and any(t > 0 for t in taken), f"{name}: coverage after the run: {texts(driver, '#coverage tr')}"
    green = [a for a, svg in graph_svgs(driver, ".graph.supervisor").items() if TAKEN in svg]
    assert green, f"{name}: no supervisor graph shows a taken transition"
    print(f"{name}: coverage after {events} events: " + "; ".join(texts(driver, "#coverage tr")))
    return taken


def findings_on_graphs(driver, name):
    """`check`'s findings listed, and their states outlined red on the graphs."""
    found = texts(driver, "#findings li")
    assert found and found != ["none"], f"{name}: no findings listed: {found}"
    red = [a for a, svg in graph_svgs(driver, ".graph").items() if FLAGGED in svg]
    assert red, f"{name}: {len(found)} findings, none outlined on a graph"
    print(f"{name}: {len(found)} findings, outlined on {', '.join(red)}")


def cell(driver, wait, url, screenshot):
    load(driver, wait, url)

    def reasons(event):
        # A disabled event's reason shows: the supervisors that disable it.
        assert any(r.strip() for r in texts(driver, "#disabled .by")), \
            f"after {event}: no disabled event with its supervisors"
        print(f"cell: disabled after {event}: {'; '.join(texts(driver, '#disabled li'))}")

    step_and_revert(driver, wait, "cell", reasons)
    taken = run(driver, wait, "cell", 1000)
    assert all(t > 0 for t in taken), f"cell: a supervisor with no coverage: {texts(driver, '#coverage tr')}"
    driver.save_screenshot(screenshot)


def factory(driver, wait, url):
    load(driver, wait, url)
    step_and_revert(driver, wait, "factory")
    run(driver, wait, "factory", 200)
    findings_on_graphs(driver, "factory")


def listening(url):
    """Waits (bounded) until a server that is still starting accepts connections on `url`'s port; returns
    the seconds waited."""
    address = urlsplit(url)
    start = time.monotonic()
    deadline = start + STARTING_S
    while True:
        try:
            socket.create_connection((address.hostname, address.port), timeout=1).close()
            return time.monotonic() - start
        except OSError:
            assert time.monotonic() < deadline, f"nothing listens on {url} after {STARTING_S} s"
            time.sleep(0.2)


def agv(driver, wait, url):
    print(f"agv: waited {listening(url):.1f} s for its server")
    load(driver, wait, url)
    # The merged supervisor of thousands of states: drawn around its current state, expanded by its button.
    partial = [b for b in driver.find_elements(By.CSS_SELECTOR, ".graph.supervisor button")
               if b.text.endswith("expand")]
    assert partial, "agv: no supervisor drawn around its current state"
    shown = int(partial[0].text.split()[1])
    graph = partial[0].find_element(By.XPATH, "..").get_attribute("data-automaton")
    partial[0].click()
    selector = f".graph[data-automaton='{graph}'] button"
    wait.until(lambda d: int(d.find_element(By.CSS_SELECTOR, selector).text.split()[1]) > shown)
    print(f"agv: {graph} expanded: {driver.find_element(By.CSS_SELECTOR, selector).text} (was {shown} states)")
    step_and_revert(driver, wait, "agv")
    run(driver, wait, "agv", 200)
    findings_on_graphs(driver, "agv")


def net(driver, wait, url):
    load(driver, wait, url)
    marking = lambda d: d.find_element(By.CSS_SELECTOR, ".graph.net .marking").text
    before = marking(driver)
    requested = driver.find_element(By.ID, "requested").text.removeprefix("Requested: ").split(", ")
    buttons = [b for b in driver.find_elements(By.CSS_SELECTOR, "#enabled button") if b.text in requested]
    assert buttons, f"net: no event the sequence requests ({requested}) is enabled"
    event = buttons[0].text
    buttons[0].click()
    wait.until(lambda d: trace_length(d) == 1)
    after = marking(driver)
    assert after != before, f"net: {event}: the marking stayed {before}"
    print(f"net: stepped {event}: marking {before} → {after}; {driver.find_element(By.ID, 'fired').text}")


def main():
    screenshot = sys.argv[1]
    urls = dict(arg.split("=", 1) for arg in sys.argv[2:])
    driver = browser()
    try:
        wait = WebDriverWait(driver, WAIT_S)
        for name, check in [("cell", cell), ("factory", factory), ("net", net), ("agv", agv)]:
            if name not in urls:
                continue
            start = time.monotonic()
            if name == "cell":
                check(driver, wait, urls[name], screenshot)
            else:
                check(driver, wait, urls[name])
            print(f"{name}: {time.monotonic() - start:.1f} s")
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
