"""`python -m server [--host H] [--port P] [--db PATH]`: run the API without the full CLI."""

import sys

from server.cli import main

if __name__ == "__main__":
    sys.exit(main())
