# SPDX-License-Identifier: MIT
"""The application: the command line (cli.py) and the accuracy-and-cost studies (study.py)."""
