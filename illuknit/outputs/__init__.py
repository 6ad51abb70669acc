"""What a user gets: previews, the hand-knitting chart, the pattern folder, the machine sheet."""
