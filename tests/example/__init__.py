"""The walk-through of docs/architecture.md ("Adding an effect"), kept here so that it is
tested: tests/gl/test_example_effect.py checks that these files are the document's code and
renders them."""
