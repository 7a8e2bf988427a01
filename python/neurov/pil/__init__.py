"""Processor in the loop: neurov's NN controller and thrust allocation, as
the firmware image runs them on an emulated Cortex-M7 (QEMU ``mps2-an500``),
flying the host's plant one control period per frame over the board's UART
(``neurov pil``, docs/firmware.md "Processor in the loop").

``framing`` (the frames), ``build`` (the image, built and cached),
``board`` (QEMU or the host build, and its link), ``loop`` (the Simulator
with the board as its controller), ``command`` (the runs compared and
written), ``cli`` (the subcommand's arguments). Nothing is imported here, so
that ``neurov --help`` stays light."""
