# SPDX-License-Identifier: MIT
"""What runs write and read back: the history table (history.py), run folders (results.py:
summary.json, history.csv, final configuration), checkpoints (checkpoint.py), the XDMF series
with its ParaView script (xdmf.py, paraview_script.py, view_template.py), and run folders read
back (rundata.py)."""
