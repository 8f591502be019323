"""What the Python checks of test/ share: print each check's outcome, write the JUnit file catkin's
test results hold, and the exit status (1 when a check failed)."""
import os
import xml.etree.ElementTree as ET


def report(suite, cases, xunit_path=None):
    """cases: [(name, [error, ...])], a check passing with no errors. Returns the exit status."""
    for name, errors in cases:
        print("%-45s %s" % (name, "ok" if not errors else "FAILED"))
        for error in errors:
            print("    " + error)
    if xunit_path:
        root = ET.Element("testsuite", name=suite, tests=str(len(cases)),
                          failures=str(sum(1 for _, errors in cases if errors)), errors="0")
        for name, errors in cases:
            case = ET.SubElement(root, "testcase", classname=suite, name=name)
            if errors:
                ET.SubElement(case, "failure", message=errors[0]).text = "\n".join(errors)
        os.makedirs(os.path.dirname(os.path.abspath(xunit_path)), exist_ok=True)
        ET.ElementTree(root).write(xunit_path, encoding="utf-8", xml_declaration=True)
    return 1 if any(errors for _, errors in cases) else 0
