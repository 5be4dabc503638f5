import telerehab


def test_package_reports_the_workspace_version():
    assert telerehab.__version__.count(".") == 2
