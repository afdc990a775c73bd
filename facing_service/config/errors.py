"""Why settings are refused: one exception for every bad flag, variable or config file."""


class SettingsError(ValueError):
    """A bad setting, as one line that names the flag or variable it came from and never
    quotes a secret (see ``disclosure``)."""
