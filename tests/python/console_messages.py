"""The console's own words, asked of the page: tests compare what a screen shows with the
catalogue's message (in whatever language the page runs) instead of waiting on English."""


def message(driver, message_id, args=None):
    """Message `message_id` of the console's catalogue as the page's `t()` gives it."""
    return driver.execute_async_script(
        "const done = arguments[arguments.length - 1], id = arguments[0], args = arguments[1] || {};"
        "import('/console/i18n.js').then(m => done(m.t(id, args))).catch(e => done('import failed: ' + e));",
        message_id, args)


def wait_saved(driver, version, wait):
    """Waits until the prescribe form says it saved `version`."""
    wait(driver, lambda d: d.find_element("id", "rx-result").get_attribute("data-saved") == str(version))
