from facing_service.contract.words import counted


def test_a_count_says_one_or_many():
    assert [counted(n, "body", "bodies") for n in (0, 1, 2)] == ["0 bodies", "1 body", "2 bodies"]


def test_how_long_a_command_runs_is_said_after_what_it_does():
    from facing_service.contract.words import for_how_long

    assert for_how_long(8.0) == " for 8 s" and for_how_long(0.25) == " for 0.25 s"
    assert for_how_long(None) == " until Ctrl-C"
