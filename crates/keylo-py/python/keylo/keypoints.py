"""The paper's keypoint study from Python: ``keylo.keypoints.evaluate``."""

from keylo._keylo import evaluate_keypoints as _evaluate


def evaluate(images, combos="paper", spec=None, jobs=1, trust_plugins=False):
    """The six keypoint metrics of every detector/descriptor combination on ``images``.

    ``images`` are 8-bit H×W numpy arrays of one sequence (each is paired with the previous
    one for the matching metrics), e.g. ``[f.signal_u8 for f in ...]`` or PNGs read with
    OpenCV. ``combos`` is ``"paper"``, ``"all"`` or names such as ``"AKAZE_AKAZE,FAST_BRIEF"``;
    ``spec`` a keypoint-evaluation spec (TOML text or file, as ``keylo keypoints eval
    --config``; None: the paper's settings). A spec naming an ONNX Runtime library of its own
    (``[params.<kind>] onnxruntime``) is refused unless ``trust_plugins=True`` (loading it
    runs its code; docs/python.md, "Trust").

    Returns ``(rows, summaries, skipped)``: a dict per image and combination with the
    columns of ``per_image.csv`` (``keypoints``, ``robustness_rotation``, ``matches``,
    ``match_ratio``, ``match_score``, ``distinctiveness``, …), a dict per combination with
    every metric's quartiles, and ``(combination, reason)`` for those this build cannot make.
    """
    return _evaluate(images, combos, spec, jobs, trust_plugins=trust_plugins)
