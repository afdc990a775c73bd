"""Settings (flags, ``FACING_*`` variables, defaults, and the zenoh session they make)
and what of them may be disclosed in logs and status (``disclosure``)."""

from .settings import Settings, SettingsError, load_settings, zenoh_config

__all__ = ["Settings", "SettingsError", "load_settings", "zenoh_config"]
