"""From ROS nodes to containers and nodes (thesis 3.2-3.3.1): ROS computation graphs, clustering ROS
nodes into containers, images by inheritance, and super-clustering onto cluster nodes.
"""

__all__ = ["image_inheritance", "resource_model", "robot_pinning", "ros_clustering", "rosgraph", "superclustering"]
