"""Python client for hrisim: REST helpers, a WebSocket lockstep Env with Gymnasium's API.

    import hrisim
    with hrisim.make("approach_human", url="http://127.0.0.1:8080", seed=7) as env:
        obs, info = env.reset()
        obs, reward, terminated, truncated, info = env.step([0.2, 0.0])

With gymnasium installed, the tasks are also registered as ``hrisim/TASK-v0``.

``Client`` and ``HrisimError`` need only the standard library; ``make`` and ``Env`` need numpy
(imported when first used).
"""

from .client import Client, HrisimError

__version__ = "0.1.0"

__all__ = ["make", "make_vec", "Env", "VectorEnv", "TASKS", "Client", "HrisimError", "Box",
           "Discrete", "decode_camera_frame", "image_observation", "register_tasks", "with_task_settings",
           "__version__"]

_ENV_NAMES = ("make", "make_vec", "Env", "VectorEnv", "TASKS", "Box", "Discrete",
              "decode_camera_frame", "image_observation", "register_tasks", "with_task_settings")


def __getattr__(name):
    if name in _ENV_NAMES:
        from . import env

        return getattr(env, name)
    raise AttributeError("module 'hrisim' has no attribute %r" % name)


def __dir__():
    return sorted(list(globals()) + list(_ENV_NAMES))


try:  # with gymnasium installed, importing hrisim registers the tasks as hrisim/TASK-v0
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:
    _gymnasium = None
if _gymnasium is not None:
    from . import env as _env  # noqa: F401  (registers on import)
