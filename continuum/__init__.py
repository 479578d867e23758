"""Continuum: a control plane for ROS-based robot software on the edge-cloud continuum."""
