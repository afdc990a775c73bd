"""tf2's four refusals, each named as tf2 names its exception (what the diagnosis and the
oracle comparisons read)."""

from __future__ import annotations

from facing_service.core.tf import errors as tf_errors


def test_each_refusal_is_a_tf_error_named_as_tf2_names_it():
    kinds = {
        tf_errors.LookupError_: "LookupException",
        tf_errors.ConnectivityError: "ConnectivityException",
        tf_errors.ExtrapolationError: "ExtrapolationException",
        tf_errors.InvalidArgumentError: "InvalidArgumentException",
    }
    for error, kind in kinds.items():
        assert issubclass(error, tf_errors.TfError) and error("x").kind == kind
    assert tf_errors.TfError.kind == "TransformException"
