from django.urls import path

from . import live, views

app_name = "realtime"
urlpatterns = [
    path("", views.overview, name="overview"),
    path("clusters/<int:pk>/", views.cluster_page, name="cluster"),
    path("clusters/<int:pk>/live/", live.cluster_live, name="cluster-live"),
    path("clusters/<int:pk>/whatif/", views.run_whatif, name="whatif"),
    path("decisions/<int:pk>/", views.decision_detail, name="decision"),
    path("plans/<int:pk>/", views.plan_detail, name="plan"),
]
