"""Drawing for the projector view: small modules of pure drawing functions over pygame surfaces.

- :mod:`palette`: colours that read on a dark table lit by a projector;
- :mod:`primitives`: anti-aliased filled shapes, thick limbs, cached glows and soft shadows;
- :mod:`life`: each character's presence over time (fade and scale in/out, speed, breathing,
  blinking) and each puck's recent path;
- :mod:`characters`: every character kind (reactor, skeleton, creature, face, sprite, figure);
- :mod:`pucks`: halo rings around the physical pucks and their fading trails;
- :mod:`screens`: the table, the "one moment" screen, the idle look and the overlay panel.
- :mod:`see_through`: the overlay panel shown through where it lies over a character;
- :mod:`images`: camera images as surfaces, for the calibration windows;
- :mod:`reading`: every word turned to read upright for a person at the table's near edge.

Positions come in projector pixels (x right, y down) from the view's table-to-projector map.
"""
