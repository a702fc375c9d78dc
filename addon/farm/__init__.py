"""Render farms (docs/farm.md): splitting a render into sample ranges and submitting them to a
scheduler. Pure Python, no bpy: `python3 addon/farm/submit.py --help`."""
