"""Pass/fail lines for the integration scripts' Python checks:

    from checklist import check, failures
    check(value < bound, f"what was measured {value} (< {bound})")
    ...
    sys.exit(1 if failures else 0)
"""

failures = []


def check(ok, text):
    """Prints the line as ok or FAIL and keeps the failures."""
    print(("ok   " if ok else "FAIL ") + text)
    if not ok:
        failures.append(text)
