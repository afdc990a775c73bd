from facing_service.contract.words import counted


def test_a_count_says_one_or_many():
    assert [counted(n, "body", "bodies") for n in (0, 1, 2)] == ["0 bodies", "1 body", "2 bodies"]
