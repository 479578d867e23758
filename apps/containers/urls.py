from django.urls import path

from . import views

app_name = "containers"
urlpatterns = [
    path("", views.rosgraph_list, name="rosgraphs"),
    path("<int:pk>/", views.rosgraph_detail, name="rosgraph"),
    path("<int:pk>/levels/", views.rosgraph_levels, name="rosgraph-levels"),
    path("<int:pk>/node/", views.rosgraph_node, name="rosgraph-node"),
    path("<int:pk>/topic/", views.rosgraph_topic, name="rosgraph-topic"),
    path("<int:pk>/cluster/", views.rosgraph_cluster, name="rosgraph-cluster"),
    path("clusterings/<int:pk>/", views.clustering_detail, name="clustering"),
    path("clusterings/<int:pk>/dockerfiles/", views.clustering_dockerfiles, name="clustering-dockerfiles"),
    path("clusterings/<int:pk>/place/", views.clustering_place, name="clustering-place"),
    path("placements/<int:pk>/", views.placement_detail, name="placement"),
    path("placements/<int:pk>/push/", views.placement_push, name="placement-push"),
]
