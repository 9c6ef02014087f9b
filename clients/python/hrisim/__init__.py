"""Python client for hrisim: REST helpers, a WebSocket lockstep Env with Gymnasium's API.

    import hrisim
    with hrisim.make("elevator", seed=7) as env:
        obs, info = env.reset()
        obs, reward, terminated, truncated, info = env.step([0.2, 0.0])

``Client`` and ``HrisimError`` need only the standard library; ``make`` and ``Env`` need numpy
(imported when first used).
"""

from .client import Client, HrisimError

__version__ = "0.1.0"

__all__ = ["make", "Env", "Client", "HrisimError", "Box", "Discrete", "decode_camera_frame",
           "__version__"]

_ENV_NAMES = ("make", "Env", "Box", "Discrete", "decode_camera_frame")


def __getattr__(name):
    if name in _ENV_NAMES:
        from . import env

        return getattr(env, name)
    raise AttributeError("module 'hrisim' has no attribute %r" % name)


def __dir__():
    return sorted(list(globals()) + list(_ENV_NAMES))
