"""Settings (flags, ``FACING_*`` variables, defaults, and the zenoh session they make)
and what of them may be disclosed in logs and status (``disclosure``)."""

from ..contract.errors import SettingsError
from .session import zenoh_config
from .settings import Settings
from .sources import load_settings

__all__ = ["Settings", "SettingsError", "load_settings", "zenoh_config"]
