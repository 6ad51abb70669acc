"""Report counts are the true counts: listed findings plus those counted but not listed."""

import json

from illuknit.check.report import CheckReport, Finding, render_report


def test_counts_include_findings_not_listed():
    listed = [Finding(i + 1, "long-float", "warning", "float of 12 needles") for i in range(200)]
    listed.append(Finding(5, "racking", "error", "racking 9 is beyond 4"))
    report = CheckReport(
        findings=tuple(listed), pieces=1, suppressed={"long-float": 130, "racking": 2}
    )
    assert (report.n_warnings, report.n_blocking) == (330, 3)
    assert len(report.findings) == 201  # the list stays capped
    text = render_report(report)
    assert "330 warning(s)" in text and "3 blocking finding(s)" in text
    assert "130 more long-float finding(s) counted, not listed" in text
    d = json.loads(report.to_json())
    assert (d["warnings"], d["blocking"], len(d["findings"])) == (330, 3, 201)
