"""Checks and facts of the config's ``measurements`` and ``kc_test`` sections that depend on
the resolved suspension (plain data, no file is read here)."""

from __future__ import annotations

from elastokin.config.schema.motion import MotionSpec
from elastokin.config.schema.suspension import MeasurementsSpec
from elastokin.config.suspension import Suspension
from elastokin.errors import ConfigError


def check_measurements(s: Suspension, m: MeasurementsSpec, key: str = "measurements") -> None:
    """Check that the ``measurements`` section fits the suspension: every part and the ground
    measured alone and given an assembly label pattern, no unknown part, joints named by
    connections, every bushing's inner (bolted) sleeve named. Errors name the key."""
    def fail(k, msg):
        return ConfigError(f"{s.source}: key '{key}.{k}': {msg}")

    needed = [s.ground, *s.parts]
    for p in needed:
        if p not in m.parts:
            raise fail("parts", f"no measurement file for part '{p}' (every part and the "
                       f"ground '{s.ground}' are measured alone)")
        if p not in m.assembly.marks:
            raise fail("assembly.marks", f"no label pattern for part '{p}'")
    for p in [*m.parts, *m.assembly.marks]:
        if p not in needed:
            raise fail("parts", f"part '{p}' is not a part of the suspension "
                       f"({', '.join(needed)})")
    connections = s.raw.get("connections", {})
    for name, jm in m.joints.items():
        if name not in connections:
            raise fail(f"joints.{name}", f"'{name}' is not a connection of the suspension")
        parts = tuple(connections[name].get("parts", ()))
        side = jm.inner or jm.bolted
        if side is not None and side not in parts:
            raise fail(f"joints.{name}", f"part '{side}' is not one of the joint's parts "
                       f"({', '.join(parts)})")
    for b in s.bushings:
        jm = m.joints.get(b.name)
        if jm is None or jm.inner is None:
            raise fail(f"joints.{b.name}.inner",
                       f"bushing '{b.name}': say which part holds the inner (bolted) sleeve: "
                       f"'{b.parts[0]}' or '{b.parts[1]}'")


def check_motion(s: Suspension, m: MotionSpec, key: str = "motion") -> None:
    """Check that the ``motion`` section fits the suspension: every part and the ground have
    a mark pattern; the other marked bodies are links (a tie rod). Errors name the key."""
    links = [name for name, c in s.raw.get("connections", {}).items()
             if c.get("type") == "link"]
    for p in [s.ground, *s.parts]:
        if p not in m.marks:
            raise ConfigError(f"{s.source}: key '{key}.marks': no label pattern for part "
                              f"'{p}' (every part and the ground '{s.ground}' are measured at "
                              "every position)")
    if m.rack_link is not None and (m.rack_link not in links or s.ground not in s.raw[
            "connections"][m.rack_link]["parts"]):
        raise ConfigError(f"{s.source}: key '{key}.rack_link': '{m.rack_link}' is not a link "
                          f"with an end on the ground '{s.ground}' (links: "
                          f"{', '.join(links) or 'none'})")
    steered = [n for n, p in m.positions.items() if p.rack_travel_mm]
    racks = [n for n, c in s.raw.get("connections", {}).items() if c.get("type") == "rack"]
    if steered and not racks and m.rack_link is None:
        raise ConfigError(f"{s.source}: key '{key}.positions.{steered[0]}.rack_travel_mm': "
                          "the suspension has no steering rack (a connection of type rack); "
                          f"name the link whose end on the ground rides on the rack "
                          f"('{key}.rack_link', e.g. the tie rod)")
    if m.wheel_marks is not None and "wheel" in m.marks:
        raise ConfigError(f"{s.source}: key '{key}.marks.wheel': 'wheel' names the wheel's "
                          "marks (wheel_marks); rename the body")
    for body in m.marks:
        if body not in (s.ground, *s.parts, *links):
            raise ConfigError(f"{s.source}: key '{key}.marks.{body}': '{body}' is not a part "
                              f"or a link of the suspension (parts: {', '.join(s.parts)}; "
                              f"links: {', '.join(links) or 'none'})")


def hardpoint_name(p, key: str, source: str) -> str:
    """``p`` when it is a hardpoint name; coordinates cannot be looked up in a measurement."""
    if not isinstance(p, str):
        raise ConfigError(f"{source}: key '{key}': give a hardpoint name (not coordinates) "
                          "so that its measurement can be found")
    return p


def hidden_stiffness(suspension: Suspension) -> dict[str, dict[str, float]]:
    """The synthetic real suspension's bushing laws in the parameters of the stiffness
    identification (:mod:`elastokin.identification.stiffness`): bushing ->
    {translation_scale, rotation_scale, translation_cubic (1/mm^2), rotation_cubic
    (1/deg^2)}; ``cubic = progression^-2``.
    Empty without ``kc_test.synthetic``. For reports only: never used in fitting."""
    s = suspension
    if s.kc_test is None or s.kc_test.synthetic is None:
        return {}
    out = {}
    for b in s.bushings:
        rb = s.kc_test.synthetic.bushings.get(b.name)
        out[b.name] = {
            "translation_scale": rb.translation_scale if rb else 1.0,
            "rotation_scale": rb.rotation_scale if rb else 1.0,
            "translation_cubic": rb.progression_mm ** -2 if rb and rb.progression_mm else 0.0,
            "rotation_cubic": rb.progression_deg ** -2 if rb and rb.progression_deg else 0.0,
        }
    return out
