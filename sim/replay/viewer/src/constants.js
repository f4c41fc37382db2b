// Words the recording uses (sim/replay/recording.py) and colours shared with sim/plot.py.
export const ROTATE_CW = "rotate clockwise";
export const ROTATE_CCW = "rotate counter-clockwise";
// matplotlib's tab10 colours in sim.plot.ROLE_COLOURS order; no role = light grey
export const ROLE_COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf"];
export const NO_ROLE_COLOUR = "#d3d3d3";
export const PACKET_COLOURS = { 1: 0xffd23f, 2: 0x22c3e6, 3: 0xffffff, 4: 0x8a8a8a };
export const LOST_COLOUR = 0xff2020;
export const PACKET_SHOWN_S = 0.15;
export const MAX_PACKET_LINES = 600;
