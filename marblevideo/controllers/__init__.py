"""Live controllers (docs/recipe-format.md, "Signals": controller signals):
OSC (:mod:`.osc`) and MIDI (:mod:`.midi`, the extra ``marblevideo[midi]``) set
the values of ``osc:/ADDRESS`` and ``midi:cc|note:CH:N`` signals
(:mod:`.values`); :mod:`.automation` writes a session's take as keyframes."""
