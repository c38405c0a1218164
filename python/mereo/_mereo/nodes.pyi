"""
Every registered node kind: mereo.nodes.<kind>(**options).
"""
from __future__ import annotations
import mereo._mereo
__all__: list = ['frame_source', 'back_project', 'identity', 'checksum', 'fail_on_frame']
def back_project(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frame's organized XYZ cloud (metres, camera frame, NaN where depth is missing).
    
    Inputs:
        frame (Frame): an RGB-D frame
    Outputs:
        cloud (Cloud): H x W x 3 points
    """
def checksum(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    A CPU-heavy, deterministic checksum of the frame's depth (engine benchmarks).
    
    Inputs:
        frame (Frame): an RGB-D frame
    Outputs:
        value (Number): the checksum
    Options:
        rounds (int, default 1, 1..1e+06): passes over the image
    """
def fail_on_frame(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Passes the frame on, but throws on the frame with the given index (error-policy tests).
    
    Inputs:
        frame (Frame): any frame
    Outputs:
        frame (Frame): the same frame
    Options:
        frame (int, default 0, 0..1e+12): index of the frame to fail on
    """
def frame_source(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    The frames of the run (a recorded sequence or a live queue), one per run step.
    
    Outputs:
        frame (Frame): the RGB-D frame
    """
def identity(**kwargs) -> mereo._mereo.NodeTemplate:
    """
    Passes the frame on unchanged (no work: measures the engine's cost per node).
    
    Inputs:
        frame (Frame): any frame
    Outputs:
        frame (Frame): the same frame
    """
