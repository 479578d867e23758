from django.urls import path

from . import views

app_name = "clusters"
urlpatterns = [
    path("clusters/", views.cluster_list, name="clusters"),
    path("clusters/<int:pk>/", views.cluster_detail, name="cluster"),
]
