from django.urls import path

from . import views

app_name = "devices"
urlpatterns = [
    path("devices/", views.device_list, name="devices"),
    path("devices/<slug:slug>/", views.device_detail, name="device"),
]
