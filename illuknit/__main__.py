"""``python -m illuknit`` runs the command line."""

from illuknit.cli import main

if __name__ == "__main__":
    main()
