"""The live state's record of drag steps the preview could not show (handlers.py reports the
first of each drag: the steps after it mostly fail alike)."""
from radiosity.core.live import LiveState


def test_a_failed_preview_is_reported_once_per_drag():
    st = LiveState()
    assert st.preview_failed("preview failed: the matrix is not rigid")
    assert st.preview_skipped == "preview failed: the matrix is not rigid"
    assert not st.preview_failed("preview failed: again")     # the same drag: kept, not told
    assert st.preview_skipped == "preview failed: again"
    st.request(now=0.0)
    assert st.take()                                          # the update after the drag
    assert st.preview_failed("preview failed: the next drag")
