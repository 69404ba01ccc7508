"""Architecture search under the microcontroller's budget."""
