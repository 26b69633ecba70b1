"""The frame a session's summaries and plots follow: the scene's end-effector."""


def end_effector(scene, links):
    """The cartesian_line trajectory's frame, else the pull's link, else the last link in the states."""
    trajectory = scene.get("trajectory") or {}
    pull = ((scene.get("interaction") or {}).get("pull") or {})
    for name in (trajectory.get("frame"), pull.get("link")):
        if name and name in links:
            return name
    return links[-1]
