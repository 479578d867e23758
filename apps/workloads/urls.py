from django.urls import path

from . import views

app_name = "workloads"
urlpatterns = [
    path("applications/", views.application_list, name="applications"),
    path("applications/<int:pk>/", views.application_detail, name="application"),
    path("applications/generate/", views.application_generate, name="application-generate"),
]
