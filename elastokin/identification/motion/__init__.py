"""Joint locations from the parts' motion (no disassembly)."""
